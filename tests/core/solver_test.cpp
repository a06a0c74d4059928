// The interior solver: the multigrid-preconditioned BiCGSTAB gives the sparse LU answer, keeps
// its hierarchy across calls, and falls back to LU when it does not converge.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/paper/boundary.h"
#include "core/paper/patch_topology.h"
#include "core/paper/solve.h"
#include "core/paper/weights.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"
#include "test_meshes.h"

namespace sdp {
namespace {

double maxDifference(const LocalUVs& a, const LocalUVs& b) {
  double worst = 0;
  for (size_t v = 0; v < a.size(); ++v)
    worst = std::max(worst, (a[v] - b[v]).cwiseAbs().maxCoeff());
  return worst;
}

// The solver's own accuracy is checked at 1e-10; the pipeline's looser default is checked by
// DefaultToleranceIsCloseToLu.
SolverSettings method(SolverMethod m) {
  SolverSettings s;
  s.method = m;
  s.tolerance = 1e-10;
  return s;
}

struct Case {
  std::string name;
  test::Mesh mesh;
  WeightScheme weights;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  all.push_back(
      {"grid",
       test::grid(140, 2.0, 1.0, [](double x, double y) { return 0.3 * std::sin(3 * x) * y; }),
       WeightScheme::MeanValue});
  // Real meshes from the extra set, when it is there (test_mesh_files.h); otherwise a curved grid
  // with the paper's weights takes their place, so that cases()[1] always exists. (The bundled
  // Nefertiti is too small for a multigrid hierarchy.)
  for (const char* name : {"camelhead", "face"}) {
    const std::string path = test::meshFile(std::string("disk/") + name + ".off");
    if (path.empty()) continue;
    const io::MeshData m = io::readMesh(path);
    all.push_back({name, {m.V, m.F}, WeightScheme::Straightest});
  }
  if (all.size() == 1) {
    all.push_back(
        {"curved grid",
         test::grid(120, 1.0, 1.0,
                    [](double x, double y) { return 0.2 * std::sin(4 * x) * std::cos(3 * y); }),
         WeightScheme::Straightest});
  }
  return all;
}

// A case's system with the circle boundary.
struct CircleSystem {
  Patch patch;
  std::vector<double> weights;
  Polygon boundary;
  LocalUVs exactSolution() const {
    return InteriorSolver(patch, method(SolverMethod::Direct)).solve(weights, boundary);
  }
};

CircleSystem circleSystem(const Case& c) {
  CircleSystem s{buildPatch(c.mesh.V, c.mesh.F), {}, {}};
  WeightCounts counts;
  s.weights = computeWeights(s.patch, c.weights, counts);
  s.boundary = circleBoundary(s.patch);
  return s;
}

TEST(InteriorSolver, MultigridMatchesSparseLu) {
  for (const Case& c : cases()) {
    const CircleSystem s = circleSystem(c);
    InteriorSolver multigrid(s.patch, method(SolverMethod::Multigrid));
    const LocalUVs expected = s.exactSolution();
    const LocalUVs got = multigrid.solve(s.weights, s.boundary);
    const SolverStats& stats = multigrid.lastStats();
    EXPECT_TRUE(stats.multigrid) << c.name;
    EXPECT_FALSE(stats.fell_back) << c.name;
    EXPECT_GT(stats.levels, 1) << c.name;
    EXPECT_LE(stats.relative_residual, 1e-10) << c.name;
    EXPECT_LT(stats.iterations, 30) << c.name;
    EXPECT_LT(maxDifference(got, expected), 1e-8) << c.name;
  }
}

// The default (loose) tolerance stays within 1e-6 of the exact solution on unit-size meshes, and
// tighten() then reaches the tight tolerance from there.
TEST(InteriorSolver, DefaultToleranceIsCloseToLuAndTightens) {
  for (const Case& c : cases()) {
    const CircleSystem s = circleSystem(c);
    SolverSettings loose;
    loose.method = SolverMethod::Multigrid;
    InteriorSolver multigrid(s.patch, loose);
    const LocalUVs expected = s.exactSolution();
    const LocalUVs got = multigrid.solve(s.weights, s.boundary);
    EXPECT_LE(multigrid.lastStats().relative_residual, loose.tolerance) << c.name;
    EXPECT_LT(maxDifference(got, expected), 1e-6) << c.name;
    ASSERT_TRUE(multigrid.tighten()) << c.name;
    EXPECT_FALSE(multigrid.tighten()) << c.name;  // already tight
    const LocalUVs tight = multigrid.solve(s.weights, s.boundary);
    EXPECT_LE(multigrid.lastStats().relative_residual, loose.tight_tolerance) << c.name;
    EXPECT_LT(maxDifference(tight, expected), 1e-9) << c.name;
  }
}

// loosen() lets later solves stop at a looser residual (fewer iterations), never after a
// tighten(): a mesh that needed tight solves keeps them.
TEST(InteriorSolver, LoosenStopsEarlierButNeverUndoesTighten) {
  const CircleSystem s = circleSystem(cases().front());
  InteriorSolver strict(s.patch, method(SolverMethod::Multigrid));
  InteriorSolver loose(s.patch, method(SolverMethod::Multigrid));
  loose.loosen(1e-4);
  strict.solve(s.weights, s.boundary);
  loose.solve(s.weights, s.boundary);
  EXPECT_LE(loose.lastStats().relative_residual, 1e-4);
  EXPECT_GT(loose.lastStats().relative_residual, 1e-8);
  EXPECT_LT(loose.lastStats().iterations, strict.lastStats().iterations);
  ASSERT_TRUE(loose.tighten());
  loose.loosen(1e-4);  // ignored: tightened
  const LocalUVs tight = loose.solve(s.weights, s.boundary);
  EXPECT_LE(loose.lastStats().relative_residual, SolverSettings().tight_tolerance);
  EXPECT_LT(maxDifference(tight, s.exactSolution()), 1e-9);
}

// u and v on two threads give the lockstep answer (each column is the same BiCGSTAB).
TEST(InteriorSolver, ParallelColumnsMatchLockstep) {
  const CircleSystem s = circleSystem(cases().front());
  SolverSettings threads = method(SolverMethod::Multigrid);
  threads.parallel_columns = true;
  InteriorSolver lockstep(s.patch, method(SolverMethod::Multigrid)), parallel(s.patch, threads);
  EXPECT_LT(
      maxDifference(lockstep.solve(s.weights, s.boundary), parallel.solve(s.weights, s.boundary)),
      1e-12);
}

// A new boundary reuses the whole hierarchy; new weights (refinement) keep the aggregates. Both
// still give the LU answer.
TEST(InteriorSolver, LaterCallsReuseTheHierarchyAndStayExact) {
  const Case c = cases()[1];
  const Patch patch = buildPatch(c.mesh.V, c.mesh.F);
  WeightCounts counts;
  std::vector<double> weights = computeWeights(patch, c.weights, counts);
  InteriorSolver direct(patch, method(SolverMethod::Direct));
  InteriorSolver multigrid(patch, method(SolverMethod::Multigrid));
  multigrid.solve(weights, circleBoundary(patch));
  EXPECT_FALSE(multigrid.lastStats().reused_hierarchy);

  const Polygon square = squareBoundary(patch);
  const LocalUVs on_square = multigrid.solve(weights, square);
  EXPECT_TRUE(multigrid.lastStats().reused_hierarchy);
  EXPECT_LT(maxDifference(on_square, direct.solve(weights, square)), 1e-8);

  // Rows reweighted as the stretch refinement does it: positive factors, renormalized.
  for (int v = 0; v < patch.vertexCount(); ++v) {
    if (patch.on_boundary[v]) continue;
    double sum = 0;
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k)
      sum += (weights[k] *= 1.0 + 0.5 * std::sin(patch.position[patch.ring_vertex[k]].x() * 7));
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) weights[k] /= sum;
  }
  const LocalUVs reweighted = multigrid.solve(weights, square);
  EXPECT_TRUE(multigrid.lastStats().reused_hierarchy);
  EXPECT_FALSE(multigrid.lastStats().fell_back);
  EXPECT_LT(maxDifference(reweighted, direct.solve(weights, square)), 1e-8);
}

// One BiCGSTAB iteration cannot reach 1e-14: the solver must hand the system to LU, say so, and
// stay with LU afterwards.
TEST(InteriorSolver, NonConvergenceFallsBackToLu) {
  const CircleSystem s = circleSystem(cases().front());
  SolverSettings hopeless = method(SolverMethod::Multigrid);
  hopeless.max_iterations = 1;
  hopeless.tolerance = 1e-14;
  InteriorSolver solver(s.patch, hopeless);
  const LocalUVs expected = s.exactSolution();
  const LocalUVs got = solver.solve(s.weights, s.boundary);
  EXPECT_TRUE(solver.lastStats().fell_back);
  EXPECT_EQ(solver.lastStats().iterations, 1);
  EXPECT_LT(solver.lastStats().relative_residual, 1e-12);  // the LU answer's
  EXPECT_LT(maxDifference(got, expected), 1e-12);
  solver.solve(s.weights, s.boundary);
  EXPECT_FALSE(solver.lastStats().multigrid);
}

// A strength threshold no connection meets leaves nothing to aggregate: the hierarchy would be
// one huge dense level, so the solver must not build it and must use LU instead.
TEST(InteriorSolver, StalledCoarseningFallsBackToLu) {
  const CircleSystem s = circleSystem(cases().front());
  SolverSettings stalled = method(SolverMethod::Multigrid);
  stalled.multigrid.strength = 10;
  InteriorSolver solver(s.patch, stalled);
  const LocalUVs got = solver.solve(s.weights, s.boundary);
  EXPECT_TRUE(solver.lastStats().fell_back);
  EXPECT_LT(maxDifference(got, s.exactSolution()), 1e-12);
}

// Automatic: LU below the size where it wins, multigrid above it.
TEST(InteriorSolver, AutomaticPicksBySize) {
  const test::Mesh small = test::planarGrid(30);
  const Patch small_patch = buildPatch(small.V, small.F);
  WeightCounts counts;
  InteriorSolver small_solver(small_patch);
  small_solver.solve(computeWeights(small_patch, WeightScheme::Uniform, counts),
                     circleBoundary(small_patch));
  EXPECT_FALSE(small_solver.lastStats().multigrid);

  const test::Mesh large = test::planarGrid(120);
  const Patch large_patch = buildPatch(large.V, large.F);
  InteriorSolver large_solver(large_patch);
  large_solver.solve(computeWeights(large_patch, WeightScheme::Uniform, counts),
                     circleBoundary(large_patch));
  EXPECT_TRUE(large_solver.lastStats().multigrid);
  EXPECT_FALSE(large_solver.lastStats().fell_back);
}

}  // namespace
}  // namespace sdp
