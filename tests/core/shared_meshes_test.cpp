// The real meshes (resources/meshes, plus the extra set in SDP_SHARED_DIR when it is there): every
// disk mesh in every combination, every invalid mesh rejected with its reason, and the paper's
// Table 1 ordering on Nefertiti. A mesh in neither place skips its test.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "core/parameterize.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"
#include "test_meshes.h"

namespace sdp {
namespace {

const char* const kDiskMeshes[] = {"nefertiti",   "snail",  "camel_b",   "lilium",
                                   "bump-domain", "circle", "camelhead", "face"};

class DiskMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(DiskMesh, AllFifteenCombinationsGiveOneToOneMaps) {
  SDP_MESH_OR_SKIP(path, std::string("disk/") + GetParam() + ".off");
  const io::MeshData mesh = io::readMesh(path);
  for (int w = 0; w < kWeightSchemeCount; ++w)
    for (int b = 0; b < kBoundaryShapeCount; ++b) {
      Options o;
      o.weights = static_cast<WeightScheme>(w);
      o.boundary = static_cast<BoundaryShape>(b);
      const Result r = parameterize(mesh.V, mesh.F, o);
      const std::string combo =
          std::string(weightSchemeName(o.weights)) + "/" + boundaryShapeName(o.boundary);
      EXPECT_EQ(r.report.flipped_faces, 0) << combo;
      EXPECT_EQ(test::countNonPositiveFaces(r, mesh.F), 0) << combo;
      EXPECT_TRUE(std::isfinite(r.report.l2_stretch)) << combo;
      EXPECT_GE(r.report.l2_stretch, 1.0 - 1e-9) << combo;
      EXPECT_GE(r.report.linf_stretch, r.report.l2_stretch - 1e-9) << combo;
    }
}

INSTANTIATE_TEST_SUITE_P(Shared, DiskMesh, ::testing::ValuesIn(kDiskMeshes), [](const auto& info) {
  std::string name = info.param;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
});

std::string reasonFor(const std::string& path) {
  try {
    const io::MeshData mesh = io::readMesh(path);
    parameterize(mesh.V, mesh.F);
  } catch (const ParameterizationError& e) {
    const std::string reason = e.what();
    EXPECT_EQ(reason.find('\n'), std::string::npos) << "not one line: " << reason;
    return reason;
  }
  return "";
}

TEST(InvalidMeshes, EachIsRejectedWithItsReason) {
  // Every invalid file there is (bundled and extra) has its expected reason here.
  const std::pair<const char*, const char*> expected[] = {
      {"3holes.off", "closed"},
      {"bumpy.off", "closed"},
      {"nan_vertex.off", "non-finite"},
      {"nonmanifold_edge.off", "non-manifold edge"},
      {"two_components.off", "2 connected components"},
      {"truncated.off", "truncated.off"}};
  const std::vector<std::string> files = test::meshFilesIn("invalid");
  ASSERT_GE(files.size(), 4u);  // the bundled ones at least
  for (const std::string& file : files) {
    const std::string name = std::filesystem::path(file).filename().string();
    const char* reason = nullptr;
    for (const auto& [n, r] : expected)
      if (name == n) reason = r;
    ASSERT_NE(reason, nullptr) << "no expected reason for " << file;
    EXPECT_NE(reasonFor(file).find(reason), std::string::npos) << file;
  }
}

// Patches with holes: inner loops are filled virtually for the solve; the map of the real
// faces is one-to-one and the fill is gone from the result.
TEST(Holes, BeetleAndHalfTunnelGiveOneToOneMaps) {
  SDP_MESH_OR_SKIP(beetle_path, "holes/beetle.off");
  SDP_MESH_OR_SKIP(tunnel_path, "holes/halftunnel_quads.off");
  for (const std::string& name : {beetle_path, tunnel_path}) {
    const io::MeshData mesh = io::readMesh(name);
    for (int b = 0; b < kBoundaryShapeCount; ++b) {
      Options o;
      o.boundary = static_cast<BoundaryShape>(b);
      const Result r = parameterize(mesh.V, mesh.F, o);
      EXPECT_EQ(r.layout.uv.rows(), mesh.V.rows()) << name;
      EXPECT_EQ(r.face_stretch.size(), static_cast<size_t>(mesh.F.rows())) << name;
      EXPECT_EQ(r.report.flipped_faces, 0) << name;
      EXPECT_EQ(test::countNonPositiveFaces(r, mesh.F), 0) << name;
      EXPECT_TRUE(std::isfinite(r.report.l2_stretch)) << name;
    }
  }
  const io::MeshData beetle = io::readMesh(beetle_path);
  const Result r = parameterize(beetle.V, beetle.F);
  EXPECT_EQ(r.report.holes_filled, 10);
  // Its 10 boundary ears would be crushed flat on the convex polygon: they are unfolded across
  // their chords instead, so the measured boundary holds (no whole-boundary fallback) and
  // stretches less than the circle.
  EXPECT_EQ(r.report.boundary_used, "measured");
  EXPECT_EQ(r.report.fallbacks[Fallback::WholeBoundary], 0);
  EXPECT_EQ(r.report.ears_unfolded, 10);
  EXPECT_EQ(test::countNonPositiveFaces(r, beetle.F), 0);
  Options circle;
  circle.boundary = BoundaryShape::Circle;
  EXPECT_LT(r.report.l2_stretch, parameterize(beetle.V, beetle.F, circle).report.l2_stretch);
}

// Strongly curved patches seen from S: most straightest walks miss their boundary vertex. Each
// miss falls back to the edge-graph distance for that vertex, counted; the measured polygon holds
// and the map stays one-to-one.
void expectMeasuredBoundaryHolds(const std::string& path) {
  const io::MeshData mesh = io::readMesh(path);
  const Result r = parameterize(mesh.V, mesh.F);
  EXPECT_EQ(r.report.boundary_used, "measured") << path;
  EXPECT_EQ(r.report.fallbacks[Fallback::WholeBoundary], 0) << path;
  EXPECT_GT(r.report.fallbacks[Fallback::DistanceWalk], 0) << path;
  EXPECT_EQ(test::countNonPositiveFaces(r, mesh.F), 0) << path;
}

TEST(MeasuredBoundary, HoldsOnCamelB) {
  SDP_MESH_OR_SKIP(path, "disk/camel_b.off");
  expectMeasuredBoundaryHolds(path);
}

TEST(MeasuredBoundary, HoldsOnCamelhead) {
  SDP_MESH_OR_SKIP(path, "disk/camelhead.off");
  expectMeasuredBoundaryHolds(path);
}

// The paper's Table 1 ordering (circle boundary): ours <= LTD <= Floater on Nefertiti.
TEST(PaperTable1, NefertitiOrderingWithCircleBoundary) {
  SDP_MESH_OR_SKIP(path, "disk/nefertiti.off");
  const io::MeshData mesh = io::readMesh(path);
  auto l2 = [&](WeightScheme w) {
    Options o;
    o.weights = w;
    o.boundary = BoundaryShape::Circle;
    return parameterize(mesh.V, mesh.F, o).report.l2_stretch;
  };
  const double ours = l2(WeightScheme::Straightest), ltd = l2(WeightScheme::Ltd),
               floater = l2(WeightScheme::Floater);
  EXPECT_LE(ours, ltd);
  EXPECT_LE(ltd, floater);
  // And the measured boundary lowers stretch further (paper Fig. 1 (c) vs (d)).
  Options measured;
  EXPECT_LT(parameterize(mesh.V, mesh.F, measured).report.l2_stretch, ours);
}

// camelhead has rings whose cutting plane crosses no far-side edge: counted, still one-to-one.
TEST(PaperTable1, CamelheadNeedsTheLtdFallbackAndCountsIt) {
  SDP_MESH_OR_SKIP(path, "disk/camelhead.off");
  const io::MeshData mesh = io::readMesh(path);
  Options o;
  o.boundary = BoundaryShape::Circle;
  const Result r = parameterize(mesh.V, mesh.F, o);
  EXPECT_GT(r.report.fallbacks[Fallback::StraightestToLtd], 0);
  // The count's warning names it, with the count first.
  const std::string warning = std::to_string(r.report.fallbacks[Fallback::StraightestToLtd]) +
                              " neighbours used the LTD direction";
  EXPECT_TRUE(std::any_of(r.report.warnings.begin(), r.report.warnings.end(),
                          [&](const std::string& w) { return w.rfind(warning, 0) == 0; }));
  EXPECT_NE(r.report.toJson().find("\"straightest_to_ltd\": " +
                                   std::to_string(r.report.fallbacks[Fallback::StraightestToLtd])),
            std::string::npos);
  EXPECT_EQ(test::countNonPositiveFaces(r, mesh.F), 0);
}

}  // namespace
}  // namespace sdp
