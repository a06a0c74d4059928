// Solver benchmark: reads a shared mesh, subdivides it k times (1-to-4 midpoint), runs the whole
// pipeline (per-stage seconds, peak memory beyond the mesh) and then times the interior solve
// alone (circle boundary) with each candidate solver; "max |x - first|" compares with the first
// candidate's answer.
//
//   solver_bench MESH [--subdivide K] [--weights NAME] [--boundary NAME] [--refine N]
//                [--no-pipeline] [--candidates LIST] [--tolerance T]
//                [--strength S] [--cycle 1|2] [--power N] [--coarsest N]
//
// LIST is comma-separated from: lu (Eigen SparseLU, the fallback), mg (the default: u and v
// together on one thread), mg-threads (u and v on two threads), vcycle (the cycle as a stationary
// iteration, and kernel timings), ilut (BiCGSTAB + ILUT), umfpack and lu-metis (only when built
// with SuiteSparse / METIS; lu-metis took 30 s on an 11k-vertex mesh). --refine N re-solves N
// times with stretch-reweighted rows, as the pipeline's refinement does. SDP_DUMP_SYSTEM=FILE
// writes the system as Matrix Market (FILE) and its right-hand sides (FILE.rhs).
#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/common/metrics.h"
#include "core/paper/boundary.h"
#include "core/paper/patch_topology.h"
#include "core/paper/solve.h"
#include "core/paper/weights.h"
#include "core/parameterize.h"
#include "io/mesh_io.h"
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
  sdp::MultigridSettings multigrid_settings;
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
    } else if (a == "--strength") {
      multigrid_settings.strength = std::stod(next());
    } else if (a == "--cycle") {
      multigrid_settings.cycle_index = std::stoi(next());
    } else if (a == "--power") {
      multigrid_settings.power_iterations = std::stoi(next());
    } else if (a == "--coarsest") {
      multigrid_settings.coarsest_size = std::stoi(next());
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

  if (const char* dump = std::getenv("SDP_DUMP_SYSTEM")) {
    std::ofstream out(dump);
    out << "%%MatrixMarket matrix coordinate real general\n"
        << system.A.rows() << " " << system.A.cols() << " " << system.A.nonZeros() << "\n";
    out.precision(17);
    for (int k = 0; k < system.A.outerSize(); ++k)
      for (SpMat::InnerIterator it(system.A, k); it; ++it)
        out << it.row() + 1 << " " << it.col() + 1 << " " << it.value() << "\n";
    std::ofstream rhs(std::string(dump) + ".rhs");
    rhs.precision(17);
    for (int i = 0; i < system.b.rows(); ++i)
      rhs << system.b(i, 0) << " " << system.b(i, 1) << "\n";
  }
  Eigen::MatrixX2d reference;
  for (const std::string& name : split(candidates)) {
    resetPeakRss();
    const long long base_kb = procStatusKb("VmRSS:");
    const auto start = Clock::now();
    const std::clock_t cpu_start = std::clock();
    Eigen::MatrixX2d x;
    std::string detail;
    if (name == "lu" || name.rfind("mg", 0) == 0) {
      sdp::SolverSettings settings;
      settings.tolerance = tolerance;
      settings.method = name == "lu" ? sdp::SolverMethod::Direct : sdp::SolverMethod::Multigrid;
      settings.parallel_columns = name == "mg-threads";
      settings.multigrid = multigrid_settings;
      sdp::InteriorSolver solver(patch, settings);
      sdp::LocalUVs previous = solver.solve(weights, boundary);
      x = interiorOf(system, previous);
      const sdp::SolverStats& st = solver.lastStats();
      char line[256];
      std::snprintf(line, sizeof line,
                    "setup %.3f s, iterate %.3f s, %d iterations, %d levels, op. complexity "
                    "%.2f, hierarchy %.0f bytes/unknown%s",
                    st.setup_seconds, st.solve_seconds, st.iterations, st.levels,
                    st.operator_complexity, double(st.hierarchy_bytes) / system.A.rows(),
                    st.fell_back ? ", FELL BACK" : "");
      detail = line;
      // Refinement re-solves as the pipeline makes them: rows reweighted by the stretch of the
      // previous map (Yoshizawa-Belyaev-Seidel, a_ij / sigma_j^eta), same pattern.
      std::vector<double> w = weights;
      for (int it = 1; it <= refine; ++it) {
        const std::vector<double> sigma = sdp::stretchMetrics(patch, previous).vertex_l2;
        for (int v = 0; v < patch.vertexCount(); ++v) {
          if (patch.on_boundary[v]) continue;
          double sum = 0;
          for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k)
            sum += (w[k] /= std::pow(std::max(sigma[patch.ring_vertex[k]], 1e-6),
                                     options.stretch_exponent));
          for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) w[k] /= sum;
        }
        const auto t = Clock::now();
        previous = solver.solve(w, boundary);
        const sdp::SolverStats& rs = solver.lastStats();
        std::printf("    re-solve %d: %.3f s, %d iterations, residual %.1e%s%s\n", it,
                    secondsSince(t), rs.iterations, rs.relative_residual,
                    rs.reused_hierarchy ? ", reused hierarchy" : "",
                    rs.fell_back ? ", FELL BACK" : "");
      }
    } else if (name == "vcycle") {
      // The V-cycle as a stationary iteration: its convergence factor, column u.
      sdp::SplitCsr A;
      A.size = static_cast<int>(system.A.rows());
      const Eigen::SparseMatrix<double, Eigen::RowMajor> R = system.A;
      A.lower.begin.push_back(0);
      A.upper.begin.push_back(0);
      A.diagonal.assign(A.size, 0.0);
      for (int i = 0; i < A.size; ++i) {
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(R, i); it; ++it)
          if (it.col() == i) {
            A.diagonal[i] = it.value();
          } else {
            sdp::CsrRows& part = it.col() < i ? A.lower : A.upper;
            part.column.push_back(static_cast<int>(it.col()));
            part.value.push_back(it.value());
          }
        A.lower.begin.push_back(static_cast<int>(A.lower.column.size()));
        A.upper.begin.push_back(static_cast<int>(A.upper.column.size()));
      }
      {
        Eigen::VectorXd xs = Eigen::VectorXd::Ones(A.size), ys(A.size);
        for (int rep = 0; rep < 3; ++rep) {
          const auto t0 = Clock::now();
          for (int it = 0; it < 10; ++it) sdp::multiply<1>(A, xs.data(), ys.data());
          std::printf("    fine SpMV %.2f ms\n", secondsSince(t0) * 100);
        }
      }
      sdp::Multigrid mg;
      const auto t_build = Clock::now();
      mg.build(A, multigrid_settings);
      std::printf("    build %.3f s\n", secondsSince(t_build));
      sdp::MultigridWorkspace work = mg.makeWorkspace(1);
      for (int l = 0; l < mg.levelCount(); ++l)
        std::printf("    level %d: %d unknowns, %.2f non-zeros per row\n", l,
                    mg.levelMatrix(l).size,
                    double(mg.levelMatrix(l).nonZeros()) / mg.levelMatrix(l).size);
      Eigen::VectorXd xu = Eigen::VectorXd::Zero(A.size), e(A.size);
      const Eigen::VectorXd bu = system.b.col(0);
      double last = bu.norm();
      {
        const auto t0 = Clock::now();
        for (int it = 0; it < 10; ++it) mg.cycle<1>(bu.data(), e.data(), work);
        std::printf("    cycle %.2f ms\n", secondsSince(t0) * 100);
        sdp::MultigridWorkspace work2 = mg.makeWorkspace(2);
        const Eigen::MatrixX2d b2 = system.b;
        Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> bi = b2, xi(A.size, 2);
        const auto t1 = Clock::now();
        for (int it = 0; it < 10; ++it) mg.cycle<2>(bi.data(), xi.data(), work2);
        std::printf("    cycle on u and v together %.2f ms\n", secondsSince(t1) * 100);
        const auto t2 = Clock::now();
        for (int it = 0; it < 10; ++it) sdp::multiply<2>(A, bi.data(), xi.data());
        std::printf("    SpMV on u and v together %.2f ms\n", secondsSince(t2) * 100);
      }
      for (int it = 1; it <= 12; ++it) {
        const Eigen::VectorXd r = bu - system.A * xu;
        mg.cycle<1>(r.data(), e.data(), work);
        xu += e;
        const double now = (bu - system.A * xu).norm();
        std::printf("    cycle %2d: residual %.2e factor %.3f\n", it, now / bu.norm(), now / last);
        last = now;
      }
      x = system.b;
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
    const double cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    const long long peak_kb = procStatusKb("VmHWM:");
    if (reference.size() == 0) reference = x;
    std::printf(
        "%-12s %7.3f s (cpu %.3f s)  residual %.1e  max |x - first| %.1e  peak +%.0f "
        "bytes/unknown  %s\n",
        name.c_str(), seconds, cpu_seconds, relativeResidual(system, x),
        (x - reference).cwiseAbs().maxCoeff(), (peak_kb - base_kb) * 1024.0 / system.A.rows(),
        detail.c_str());
    std::fflush(stdout);
  }
  return 0;
}
