// The map one-to-one as stored (docs/method.md §5) and the refinement's stopping rule (§4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/common/storage.h"
#include "core/parameterize.h"
#include "core/refine/free_boundary.h"
#include "core/refine/stretch_newton.h"
#include "test_meshes.h"

namespace sdp {
namespace {

// A gently curved grid whose centre vertex sits 1e-7 of an edge from its neighbour: one-to-one
// in double, but its two needle faces collapse in float or in 6 decimals.
test::Mesh needleGrid() {
  test::Mesh m = test::grid(8, 1, 1, [](double x, double y) { return 0.1 * std::sin(3 * x + y); });
  const int v = 4 * 9 + 4, w = 4 * 9 + 5;
  m.V.row(v) = m.V.row(v) + (m.V.row(w) - m.V.row(v)) * (1 - 1e-7);
  return m;
}

// What MeshLab's OBJ exporter writes for a stored float ("%f"), read back.
double asObjText(double stored) {
  char text[64];
  std::snprintf(text, sizeof text, "%f", static_cast<double>(static_cast<float>(stored)));
  return std::strtod(text, nullptr);
}

int nonPositiveFaces(const UVs& uv, const Triangles& F, double (*as_stored)(double)) {
  int bad = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    double p[3][2];
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 2; ++k) p[c][k] = as_stored(uv(F(f, c), k));
    const double cross =
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    if (!(cross > 0)) ++bad;
  }
  return bad;
}

double asFloat(double x) {
  return static_cast<float>(x);
}

// The needle grid fitted to the unit square and stored as `storage` says.
Result storedNeedleGrid(const test::Mesh& m, UVStorage storage) {
  Options o;
  o.storage.fit_unit_square = true;
  o.storage.precision = storage;
  return parameterize(m.V, m.F, o);
}

TEST(Storage, NeedleFacesCollapseWhenRoundedNaively) {
  const test::Mesh m = needleGrid();
  const Result r = storedNeedleGrid(m, UVStorage::Double);
  EXPECT_EQ(nonPositiveFaces(r.layout.uv, m.F, [](double x) { return x; }), 0);
  EXPECT_GT(nonPositiveFaces(r.layout.uv, m.F, asFloat), 0) << "the case no longer needs a repair";
  EXPECT_GT(nonPositiveFaces(r.layout.uv, m.F, asObjText), 0)
      << "the case no longer needs a repair";
  EXPECT_EQ(r.report.storage, "double");
  EXPECT_EQ(r.report.storage_degenerate_faces, 0);
}

TEST(Storage, MeshLabStorageIsRepairedAndExact) {
  const test::Mesh m = needleGrid();
  const Result r = storedNeedleGrid(m, UVStorage::FloatAndSixDecimals);
  EXPECT_EQ(r.report.storage, "float, 6 decimals");
  EXPECT_EQ(r.report.storage_degenerate_faces, 2);
  EXPECT_GT(r.report.storage_moved_vertices, 0);
  EXPECT_EQ(r.report.flipped_faces, 0);
  // Repaired, so a note, not a warning.
  ASSERT_EQ(r.report.notes.size(), 1u);
  EXPECT_EQ(r.report.notes[0].rfind("stored one-to-one: 2 faces would have collapsed", 0), 0u)
      << r.report.notes[0];
  for (const std::string& w : r.report.warnings)
    EXPECT_EQ(w.find("collapse"), std::string::npos) << w;
  for (Eigen::Index i = 0; i < r.layout.uv.rows(); ++i)
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(asFloat(r.layout.uv(i, k)), r.layout.uv(i, k)) << "not a float: vertex " << i;
      EXPECT_NEAR(asObjText(r.layout.uv(i, k)), r.layout.uv(i, k), 3e-8)
          << "not 6 decimals: vertex " << i;
    }
  EXPECT_EQ(nonPositiveFaces(r.layout.uv, m.F, asFloat), 0);
  EXPECT_EQ(nonPositiveFaces(r.layout.uv, m.F, asObjText), 0);
  // The report describes the stored map.
  const UVMeasures stored = measureUVs(m.V, m.F, r.layout.uv);
  EXPECT_DOUBLE_EQ(stored.l2_stretch, r.report.l2_stretch);
  EXPECT_DOUBLE_EQ(stored.linf_stretch, r.report.linf_stretch);
}

TEST(Storage, FloatStorageIsRepaired) {
  const test::Mesh m = needleGrid();
  const Result r = storedNeedleGrid(m, UVStorage::Float);
  EXPECT_EQ(r.report.storage_degenerate_faces, 2);
  EXPECT_EQ(nonPositiveFaces(r.layout.uv, m.F, asFloat), 0);
}

TEST(Storage, BorderThatRoundingMakesTouchItselfIsSeparated) {
  // One chart of two triangles whose corners lie 3e-9 apart: apart in double, one point once
  // rounded to float or 6 decimals, so the chart's border would touch itself as stored. The
  // corners move into their own faces instead of the map being refused.
  for (const UVStorage storage : {UVStorage::Float, UVStorage::FloatAndSixDecimals}) {
    const double e = 3e-9;
    Layout layout;
    layout.uv.resize(6, 2);
    layout.uv << 0.2, 0.2, 0.5, 0.2, 0.5, 0.5, 0.5 + e, 0.5 + e, 0.8, 0.5, 0.8, 0.8;
    layout.face_uv.resize(2, 3);
    layout.face_uv << 0, 1, 2, 3, 4, 5;
    layout.chart = {0, 0};
    ASSERT_TRUE(edgesAreSimple(
        {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}},
        LocalUVs{{0.2, 0.2}, {0.5, 0.2}, {0.5, 0.5}, {0.5 + e, 0.5 + e}, {0.8, 0.5}, {0.8, 0.8}}));
    StoragePolicy policy;
    policy.precision = storage;
    const StorageCounts counts = store(layout, policy);
    EXPECT_GE(counts.moved_vertices, 1);
    LocalUVs stored;
    for (int r = 0; r < 6; ++r) stored.push_back(layout.uv.row(r).transpose());
    EXPECT_TRUE(edgesAreSimple({{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}}, stored));
    EXPECT_LT((stored[2] - Eigen::Vector2d(0.5, 0.5)).norm(), 0.01);  // a small move
  }
}

TEST(Storage, UnitSquareFitSpansZeroToOne) {
  const test::Mesh m = test::grid(6, 2, 1, [](double x, double y) { return 0.2 * x * y; });
  Options o;
  o.storage.fit_unit_square = true;
  o.storage.precision = UVStorage::FloatAndSixDecimals;
  const Result r = parameterize(m.V, m.F, o);
  const double low = std::min(r.layout.uv.col(0).minCoeff(), r.layout.uv.col(1).minCoeff());
  const double high = std::max(r.layout.uv.col(0).maxCoeff(), r.layout.uv.col(1).maxCoeff());
  EXPECT_NEAR(low, 0, 1e-6);
  EXPECT_NEAR(high, 1, 1e-6);
  EXPECT_EQ(r.report.storage_degenerate_faces, 0);
}

// docs/method.md §4: the product default refines and stops on measured progress or on its work
// budget, which is counted, not timed: the same result on every run.
TEST(Refinement, DefaultsRefineAndStopOnProgress) {
  const test::Mesh m = test::grid(12, 1, 1, [](double x, double y) { return 0.6 * x * x * y; });
  const Options o = productDefaults();
  EXPECT_EQ(o.stretch_iterations, kDefaultStretchIterations);
  EXPECT_GT(o.refine_work_factor, 0);
  EXPECT_EQ(o.time_limit_seconds, 0) << "no wall-clock limit by default";
  const Result a = parameterize(m.V, m.F, o), b = parameterize(m.V, m.F, o);
  EXPECT_LT(a.report.l2_stretch, a.report.l2_stretch_linear);
  EXPECT_TRUE(a.report.refinement_stop == "converged" || a.report.refinement_stop == "iterations")
      << a.report.refinement_stop;
  EXPECT_TRUE(a.layout.uv.isApprox(b.layout.uv, 0)) << "the default is not deterministic";
  EXPECT_GT(a.report.refinement_work, 0);
  EXPECT_EQ(a.report.refinement_work, b.report.refinement_work);
  Options linear;
  EXPECT_EQ(parameterize(m.V, m.F, linear).report.refinement_stop, "not run");
}

// A small work budget stops the refinement at a step that depends on counted work alone.
TEST(Refinement, WorkBudgetStopsAtTheSameStepEveryRun) {
  const test::Mesh m = test::grid(40, 1, 1, [](double x, double y) { return 0.6 * x * x * y; });
  Options o = productDefaults();
  o.refine_min_gain = 0;
  o.refine_min_work = 0;
  o.refine_work_factor = 1;  // about one reweighting step
  const Result a = parameterize(m.V, m.F, o), b = parameterize(m.V, m.F, o);
  EXPECT_EQ(a.report.refinement_stop, "work budget");
  EXPECT_LT(a.report.stretch_iterations_run, o.stretch_iterations);
  EXPECT_LT(a.report.refinement_work, 2 * o.refine_work_factor) << "overran by more than a step";
  EXPECT_EQ(a.report.stretch_iterations_run, b.report.stretch_iterations_run);
  EXPECT_TRUE(a.layout.uv.isApprox(b.layout.uv, 0));
}

// Past the sparse factor's size the Newton stage starts with the grid's steps, a fine step
// costing several of them: the budget's prediction changes with the kind of step, so the
// hand-over to the fine steps does not overrun (it did, by a fifth, on an 845k-vertex scan).
TEST(Refinement, LargePatchesStayWithinTheBudgetAcrossStepKinds) {
  const test::Mesh m = test::grid(240, 1, 1, [](double x, double y) {
    return 0.15 * std::sin(9 * x) * std::sin(7 * y) + 0.3 * x * x;
  });
  Options o = productDefaults();
  o.refine_min_work = 0;
  for (const double factor : {1.0, 1.5, 2.0, 3.0}) {
    o.refine_work_factor = factor;
    const Result r = parameterize(m.V, m.F, o);
    ASSERT_GT(r.report.vertices, StretchNewtonSettings().direct_up_to);
    std::printf("budget %.1f: work %.3f, %d free-boundary steps, L2 %.5f\n", factor,
                r.report.refinement_work, r.report.free_boundary_steps, r.report.l2_stretch);
    if (factor >= 1.5) {  // room for grid steps after the reweighting's share
      EXPECT_GT(r.report.free_boundary_steps, 0);
      EXPECT_LT(r.report.l2_stretch, r.report.l2_stretch_fixed_boundary);
    }
    EXPECT_LE(r.report.refinement_work, 1.05 * factor);
    EXPECT_EQ(test::countNonPositiveFaces(r, m.F), 0);
  }
}

TEST(Refinement, ZeroMinGainRunsEveryIteration) {
  const test::Mesh m = test::grid(10, 1, 1, [](double x, double y) { return 0.5 * x * y; });
  Options o;
  o.stretch_iterations = 4;
  o.free_boundary = false;
  o.refine_min_gain = 0;
  const Result r = parameterize(m.V, m.F, o);
  EXPECT_EQ(r.report.stretch_iterations_run, 4);
  EXPECT_EQ(r.report.refinement_stop, "iterations");
}

}  // namespace
}  // namespace sdp

namespace sdp {
namespace {

// parameterize() is flattenDisk() followed by the store step: the same bytes either way, and
// flattenDisk's layout is at the mesh's own scale (3D units) until it is stored.
TEST(StoreStep, ParameterizeIsFlattenDiskThenStore) {
  const test::Mesh m = test::grid(20, 3, 2, [](double x, double y) { return 0.4 * x * y; });
  Options o = productDefaults();
  o.storage.fit_unit_square = true;
  o.storage.precision = UVStorage::FloatAndSixDecimals;
  const Result stored = parameterize(m.V, m.F, o);
  Result flat = flattenDisk(m.V, m.F, o);
  const double extent =
      (flat.layout.uv.colwise().maxCoeff() - flat.layout.uv.colwise().minCoeff()).maxCoeff();
  EXPECT_GT(extent, 2.0) << "not at the mesh's scale (3 x 2 units)";
  StoragePolicy policy;
  policy.fit_unit_square = true;
  policy.precision = UVStorage::FloatAndSixDecimals;
  store(flat.layout, policy);
  EXPECT_TRUE(flat.layout.uv == stored.layout.uv);
  EXPECT_TRUE(flat.layout.face_uv == stored.layout.face_uv);
  EXPECT_NEAR(stored.layout.uv.maxCoeff(), 1.0, 1e-6);
}

// The store step certifies per chart: a layout of two charts, the second mirrored, is stored
// (each chart is one-to-one on its own), while a face folded inside a chart is refused.
TEST(StoreStep, CertifiesEachChartOnItsOwn) {
  Layout layout;
  layout.uv.resize(6, 2);
  layout.uv << 0, 0, 1, 0, 0, 1, 3, 0, 2, 0, 3, 1;  // chart 1 runs clockwise
  layout.face_uv.resize(2, 3);
  layout.face_uv << 0, 1, 2, 3, 4, 5;
  layout.chart = {0, 1};
  Layout two = layout;
  int steps = 0;  // a front end's progress bar is called between the store's steps
  EXPECT_NO_THROW(store(two, StoragePolicy{}, [&] { ++steps; }));
  EXPECT_EQ(steps, 3);
  layout.chart = {0, 0};  // one chart: the second face is flipped against the first
  EXPECT_THROW(store(layout, StoragePolicy{}), ParameterizationError);
}

}  // namespace
}  // namespace sdp
