#include <gtest/gtest.h>

#include "core/parameterize.h"
#include "test_meshes.h"

namespace sdp {
namespace {

Options with(WeightScheme w, BoundaryShape b) {
  Options o;
  o.weights = w;
  o.boundary = b;
  return o;
}

// docs/method.md §3: a planar patch with the measured boundary comes back as itself, up to a
// similarity.
TEST(Parameterize, PlanarPatchWithMeasuredBoundaryIsIsometric) {
  const test::Mesh m = test::planarGrid(16);
  for (WeightScheme w : {WeightScheme::Straightest, WeightScheme::Ltd, WeightScheme::Floater,
                         WeightScheme::MeanValue}) {
    const Result r = parameterize(m.V, m.F, with(w, BoundaryShape::Measured));
    EXPECT_NEAR(r.report.l2_stretch, 1.0, 1e-6) << weightSchemeName(w);
    EXPECT_NEAR(r.report.linf_stretch, 1.0, 1e-3) << weightSchemeName(w);
    EXPECT_EQ(r.report.boundary_used, "measured");
    EXPECT_EQ(r.report.fallbacks.total(), 0);
    EXPECT_EQ(test::countNonPositiveFaces(r, m.F), 0);
  }
}

TEST(Parameterize, ResultShapesAndReportKeys) {
  const test::Mesh m = test::grid(10, 1, 1, [](double x, double y) { return x * y; });
  const Result r = parameterize(m.V, m.F);
  EXPECT_EQ(r.layout.uv.rows(), m.V.rows());
  EXPECT_EQ(r.face_stretch.size(), static_cast<size_t>(m.F.rows()));
  EXPECT_EQ(r.report.vertices, m.V.rows());
  EXPECT_EQ(r.report.faces, m.F.rows());
  EXPECT_GE(r.report.source_vertex, 0);
  EXPECT_GT(r.report.seconds, 0);
  const std::string json = r.report.toJson();
  for (const char* key : {"\"l2_stretch\"", "\"linf_stretch\"", "\"flipped_faces\"",
                          "\"fallbacks\"", "\"source_vertex\"", "\"seconds\"", "\"vertices\"",
                          "\"faces\"", "\"weights\"", "\"boundary\"", "\"stage_seconds\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

// A user could fairly expect a map here: it is the boundary polygon itself.
TEST(Parameterize, OneTriangleAndNoInteriorVertexGiveValidMaps) {
  Positions V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Triangles F(1, 3);
  F << 0, 1, 2;
  for (BoundaryShape b : {BoundaryShape::Measured, BoundaryShape::Circle, BoundaryShape::Square}) {
    const Result r = parameterize(V, F, with(WeightScheme::Straightest, b));
    EXPECT_EQ(r.report.flipped_faces, 0);
    EXPECT_EQ(test::countNonPositiveFaces(r, F), 0);
    EXPECT_EQ(r.report.boundary_used, "circle");
  }
  // A strip of four triangles: every vertex on the boundary.
  Positions S(6, 3);
  S << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
  Triangles G(4, 3);
  G << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
  const Result r = parameterize(S, G, with(WeightScheme::Straightest, BoundaryShape::Square));
  EXPECT_EQ(test::countNonPositiveFaces(r, G), 0);
}

TEST(Parameterize, SourceVertexIsValidated) {
  const test::Mesh m = test::planarGrid(6);
  Options o;
  o.source_vertex = 1000;
  EXPECT_THROW(
      {
        try {
          parameterize(m.V, m.F, o);
        } catch (const ParameterizationError& e) {
          EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos);
          throw;
        }
      },
      ParameterizationError);
  o.source_vertex = 0;  // a corner: on the boundary
  EXPECT_THROW(parameterize(m.V, m.F, o), ParameterizationError);
  o.source_vertex = 3 * 7 + 3;
  EXPECT_EQ(parameterize(m.V, m.F, o).report.source_vertex, 3 * 7 + 3);
}

// Moving the mesh far away or shrinking it must not change the map (up to scale).
TEST(Parameterize, ScaleAndTranslationInvariant) {
  const test::Mesh m =
      test::grid(20, 1, 1, [](double x, double y) { return 0.4 * std::sin(3 * x + 2 * y); });
  const Result base = parameterize(m.V, m.F);
  // (scale, offset) pairs; a tiny mesh far away is not representable in doubles, so not both.
  const double cases[][2] = {{1e-6, 0}, {1e6, 0}, {1, 1e6}, {1, -1e6}, {1e3, 1e6}};
  for (const auto& c : cases) {
    const double scale = c[0], offset = c[1];
    Positions V = m.V * scale;
    V.array() += offset;
    const Result r = parameterize(V, m.F);
    EXPECT_NEAR(r.report.l2_stretch, base.report.l2_stretch, 1e-6 * base.report.l2_stretch)
        << "scale " << scale << " offset " << offset;
    EXPECT_EQ(r.report.source_vertex, base.report.source_vertex);
    EXPECT_EQ(r.report.flipped_faces, 0);
  }
}

TEST(Parameterize, StretchIterationsLowerStretchAndNeverFold) {
  const test::Mesh m = test::grid(24, 1, 1, [](double x, double y) {
    return 0.8 * std::exp(-20 * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5)));
  });
  Options o = with(WeightScheme::Straightest, BoundaryShape::Circle);
  const Result linear = parameterize(m.V, m.F, o);
  o.stretch_iterations = 5;
  const Result refined = parameterize(m.V, m.F, o);
  EXPECT_LT(refined.report.l2_stretch, linear.report.l2_stretch);
  EXPECT_NEAR(refined.report.l2_stretch_linear, linear.report.l2_stretch, 1e-12);
  EXPECT_GT(refined.report.best_iteration, 0);
  EXPECT_EQ(test::countNonPositiveFaces(refined, m.F), 0);
}

TEST(Parameterize, ProgressIsReportedAndCancelStops) {
  const test::Mesh m = test::planarGrid(8);
  Options o;
  std::vector<int> seen;
  o.progress = [&](const char*, int percent) {
    seen.push_back(percent);
    return true;
  };
  parameterize(m.V, m.F, o);
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(seen.back(), 100);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  o.progress = [](const char* stage, int) { return std::string(stage) != "solve"; };
  try {
    parameterize(m.V, m.F, o);
    FAIL() << "not cancelled";
  } catch (const ParameterizationError& e) {
    EXPECT_STREQ(e.what(), "cancelled by the user");
  }
}

// The refinement's free-boundary steps (which can take seconds) ask too, before every step: a
// cancel at the first as-rigid-as-possible step (the second "free boundary" call; the first
// opens the stage) or at the first Newton step (percent 97) stops the run.
TEST(Parameterize, CancelStopsTheFreeBoundarySteps) {
  const test::Mesh m = test::grid(10, 1, 1, [](double x, double y) { return 0.3 * x * y; });
  for (const bool in_newton : {false, true}) {
    Options o;
    o.stretch_iterations = 3;
    int free_boundary_calls = 0, last_percent = -1;
    o.progress = [&](const char* stage, int percent) {
      last_percent = percent;
      if (std::string(stage) != "free boundary") return true;
      ++free_boundary_calls;
      return in_newton ? percent < 97 : free_boundary_calls < 2;
    };
    try {
      parameterize(m.V, m.F, o);
      FAIL() << "not cancelled, in_newton " << in_newton;
    } catch (const ParameterizationError& e) {
      EXPECT_STREQ(e.what(), "cancelled by the user");
    }
    EXPECT_EQ(last_percent, in_newton ? 97 : 95);
  }
}

TEST(Parameterize, NeedleAndZeroAreaTrianglesStillGiveAOneToOneMap) {
  test::Mesh m = test::planarGrid(8);
  // Put an interior vertex on the far edge of one of its faces: that face has zero area.
  const int v = 4 * 9 + 4;  // (i + j) even: its cell has face (v, v + 1, v + 10)
  m.V.row(v) = 0.5 * (m.V.row(v + 1) + m.V.row(v + 10));
  const Result r = parameterize(m.V, m.F, with(WeightScheme::Straightest, BoundaryShape::Circle));
  EXPECT_EQ(test::countNonPositiveFaces(r, m.F), 0);
  EXPECT_GE(r.report.fallbacks[Fallback::DegenerateRing], 1);
}

}  // namespace
}  // namespace sdp
