// Solver benchmark: reads a shared mesh, subdivides it k times (1-to-4 midpoint), runs the whole
// pipeline (per-stage seconds, peak memory beyond the mesh) and then times the interior solve
// alone with each candidate solver, against the sparse LU answer.
//
//   solver_bench MESH [--subdivide K] [--weights NAME] [--boundary NAME] [--refine N]
//                [--no-pipeline] [--candidates LIST] [--tolerance T]
//
// LIST is comma-separated from: lu, mg (u and v on two threads), mg-lockstep (one thread, u and
// v together), mg-rebuild (refinement rebuilds the hierarchy), ilut (BiCGSTAB + ILUT), umfpack
// and lu-metis (when built with SuiteSparse / METIS).
#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/boundary.h"
#include "core/parameterize.h"
#include "core/patch.h"
#include "core/solve.h"
#include "core/weights.h"
#include "mesh_io.h"
#include "midpoint_subdivision.h"

#ifdef SDP_BENCH_UMFPACK
#include <Eigen/UmfPackSupport>
#endif
#ifdef SDP_BENCH_METIS
#include <Eigen/MetisSupport>
#endif

namespace {

using Clock = std::chrono::steady_clock;
using SpMat = Eigen::SparseMatrix<double>;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

long long procStatusKb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stoll(line.substr(std::strlen(key)));
  return -1;
}

// Resets the kernel's peak-RSS counter so VmHWM measures from here on.
void resetPeakRss() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

struct System {
  SpMat A;
  Eigen::MatrixX2d b;
  std::vector<int> unknown;
};

System assemble(const sdp::Patch& p, const std::vector<double>& w, const sdp::Polygon& boundary) {
  System s;
  s.unknown.assign(p.vertexCount(), -1);
  int n = 0;
  for (int v = 0; v < p.vertexCount(); ++v)
    if (!p.on_boundary[v]) s.unknown[v] = n++;
  std::vector<Eigen::Vector2d> fixed(p.vertexCount(), Eigen::Vector2d::Zero());
  for (size_t k = 0; k < p.boundary_loop.size(); ++k) fixed[p.boundary_loop[k]] = boundary[k];
  std::vector<Eigen::Triplet<double>> t;
  s.b = Eigen::MatrixX2d::Zero(n, 2);
  for (int v = 0; v < p.vertexCount(); ++v) {
    const int row = s.unknown[v];
    if (row < 0) continue;
    t.emplace_back(row, row, 1.0);
    for (int k = p.ring_begin[v]; k < p.ring_begin[v + 1]; ++k) {
      const int j = p.ring_vertex[k];
      if (s.unknown[j] >= 0)
        t.emplace_back(row, s.unknown[j], -w[k]);
      else
        s.b.row(row) += w[k] * fixed[j].transpose();
    }
  }
  s.A.resize(n, n);
  s.A.setFromTriplets(t.begin(), t.end());
  s.A.makeCompressed();
  return s;
}

double relativeResidual(const System& s, const Eigen::MatrixX2d& x) {
  const Eigen::MatrixX2d r = s.b - s.A * x;
  return std::max(r.col(0).norm() / s.b.col(0).norm(), r.col(1).norm() / s.b.col(1).norm());
}

Eigen::MatrixX2d interiorOf(const System& s, const sdp::LocalUVs& uv) {
  Eigen::MatrixX2d x(s.b.rows(), 2);
  for (size_t v = 0; v < uv.size(); ++v)
    if (s.unknown[v] >= 0) x.row(s.unknown[v]) = uv[v].transpose();
  return x;
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: solver_bench MESH [--subdivide K] [--weights NAME] ...\n");
    return 2;
  }
  std::string path = argv[1], candidates = "lu,mg";
  int subdivide = 0, refine = 0;
  bool pipeline = true;
  double tolerance = sdp::SolverSettings{}.tolerance;
  sdp::Options options;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--subdivide") {
      subdivide = std::stoi(next());
    } else if (a == "--weights") {
      options.weights = *sdp::parseWeightScheme(next());
    } else if (a == "--boundary") {
      options.boundary = *sdp::parseBoundaryShape(next());
    } else if (a == "--refine") {
      refine = std::stoi(next());
    } else if (a == "--no-pipeline") {
      pipeline = false;
    } else if (a == "--candidates") {
      candidates = next();
    } else if (a == "--tolerance") {
      tolerance = std::stod(next());
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  options.stretch_iterations = refine;

  sdp::io::MeshData mesh = sdp::io::readMesh(path);
  for (int k = 0; k < subdivide; ++k) sdp::bench::subdivideMidpoint(mesh.V, mesh.F);
  std::printf("mesh %s subdivided %d times: %ld vertices, %ld faces\n", path.c_str(), subdivide,
              static_cast<long>(mesh.V.rows()), static_cast<long>(mesh.F.rows()));

  if (pipeline) {
    resetPeakRss();
    const long long base_kb = procStatusKb("VmRSS:");
    const sdp::Result r = sdp::parameterize(mesh.V, mesh.F, options);
    const long long peak_kb = procStatusKb("VmHWM:");
    std::printf("pipeline %.3f s (weights %s, boundary %s -> %s, refine %d, flipped %d)\n",
                r.report.seconds, r.report.weights.c_str(), r.report.boundary.c_str(),
                r.report.boundary_used.c_str(), r.report.stretch_iterations_run,
                r.report.flipped_faces);
    for (const auto& [stage, s] : r.report.stage_seconds)
      std::printf("  stage %-9s %.3f s\n", stage.c_str(), s);
    std::printf("  peak RSS beyond the mesh: %.1f MB = %.0f bytes/vertex\n",
                (peak_kb - base_kb) / 1024.0, (peak_kb - base_kb) * 1024.0 / mesh.V.rows());
  }

  // The solve alone, on the circle boundary (always the same system whatever S is).
  const sdp::Patch patch = sdp::buildPatch(mesh.V, mesh.F);
  sdp::WeightCounts counts;
  const std::vector<double> weights = sdp::computeWeights(patch, options.weights, counts);
  const sdp::Polygon boundary = sdp::circleBoundary(patch);
  const System system = assemble(patch, weights, boundary);
  std::printf("system: %ld unknowns, %ld non-zeros\n", static_cast<long>(system.A.rows()),
              static_cast<long>(system.A.nonZeros()));

  Eigen::MatrixX2d reference;
  for (const std::string& name : split(candidates)) {
    resetPeakRss();
    const long long base_kb = procStatusKb("VmRSS:");
    const auto start = Clock::now();
    Eigen::MatrixX2d x;
    std::string detail;
    if (name == "lu" || name.rfind("mg", 0) == 0) {
      sdp::SolverSettings settings;
      settings.tolerance = tolerance;
      settings.method = name == "lu" ? sdp::SolverMethod::Direct : sdp::SolverMethod::Multigrid;
      settings.parallel_columns = name != "mg-lockstep";
      settings.rebuild_on_new_weights = name == "mg-rebuild";
      sdp::InteriorSolver solver(patch, settings);
      x = interiorOf(system, solver.solve(weights, boundary));
      const sdp::SolverStats& st = solver.lastStats();
      char line[256];
      std::snprintf(line, sizeof line,
                    "setup %.3f s, iterate %.3f s, %d iterations, %d levels, op. complexity "
                    "%.2f, hierarchy %.0f bytes/unknown%s",
                    st.setup_seconds, st.solve_seconds, st.iterations, st.levels,
                    st.operator_complexity, double(st.hierarchy_bytes) / system.A.rows(),
                    st.fell_back ? ", FELL BACK" : "");
      detail = line;
      // Refinement-like re-solves: stretch-reweighted rows on the same pattern.
      std::vector<double> w = weights;
      for (int it = 1; it <= refine; ++it) {
        for (int v = 0; v < patch.vertexCount(); ++v) {
          if (patch.on_boundary[v]) continue;
          double sum = 0;
          for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k)
            sum += (w[k] *= 1.0 + 0.5 * std::sin(0.001 * patch.ring_vertex[k] * it));
          for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) w[k] /= sum;
        }
        const auto t = Clock::now();
        solver.solve(w, boundary);
        const sdp::SolverStats& rs = solver.lastStats();
        std::printf("    re-solve %d: %.3f s, %d iterations, residual %.1e%s%s\n", it,
                    secondsSince(t), rs.iterations, rs.relative_residual,
                    rs.reused_hierarchy ? ", reused hierarchy" : "",
                    rs.fell_back ? ", FELL BACK" : "");
      }
    } else if (name == "ilut") {
      Eigen::BiCGSTAB<SpMat, Eigen::IncompleteLUT<double>> solver;
      solver.setTolerance(tolerance);
      solver.setMaxIterations(2000);
      solver.preconditioner().setDroptol(1e-4);
      solver.preconditioner().setFillfactor(4);
      solver.compute(system.A);
      x = solver.solve(system.b);
      detail = "iterations " + std::to_string(solver.iterations());
#ifdef SDP_BENCH_UMFPACK
    } else if (name == "umfpack") {
      Eigen::UmfPackLU<SpMat> lu(system.A);
      x = lu.solve(system.b);
#endif
#ifdef SDP_BENCH_METIS
    } else if (name == "lu-metis") {
      Eigen::SparseLU<SpMat, Eigen::MetisOrdering<int>> lu(system.A);
      x = lu.solve(system.b);
#endif
    } else {
      std::printf("%-12s not built in\n", name.c_str());
      continue;
    }
    const double seconds = secondsSince(start);
    const long long peak_kb = procStatusKb("VmHWM:");
    if (reference.size() == 0) reference = x;
    std::printf(
        "%-12s %7.3f s  residual %.1e  max |x - first| %.1e  peak +%.0f bytes/unknown  %s\n",
        name.c_str(), seconds, relativeResidual(system, x), (x - reference).cwiseAbs().maxCoeff(),
        (peak_kb - base_kb) * 1024.0 / system.A.rows(), detail.c_str());
    std::fflush(stdout);
  }
  return 0;
}
