#include <gtest/gtest.h>

#include "core/common/metrics.h"
#include "core/paper/patch_topology.h"
#include "test_meshes.h"

namespace sdp {
namespace {

std::vector<Eigen::Vector2d> affineUVs(const Patch& patch, const Eigen::Matrix2d& A) {
  std::vector<Eigen::Vector2d> uv;
  for (const auto& q : patch.position) uv.push_back(A * Eigen::Vector2d(q.x(), q.y()));
  return uv;
}

TEST(Metrics, FaceStretchOfKnownAffineMaps) {
  const Eigen::Vector3d q[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  // uv = (2x, y): the 2D -> 3D map has singular values 1/2 and 1.
  const Eigen::Vector2d p[3] = {{0, 0}, {2, 0}, {0, 1}};
  const FaceStretch s = faceStretch(q, p);
  EXPECT_NEAR(s.l2, std::sqrt((0.25 + 1.0) / 2), 1e-12);
  EXPECT_NEAR(s.linf, 1.0, 1e-12);
  EXPECT_NEAR(s.area2d, 1.0, 1e-12);
  EXPECT_NEAR(s.area3d, 0.5, 1e-12);
  // A rotation is isometric.
  const double c = std::cos(0.7), si = std::sin(0.7);
  const Eigen::Vector2d r[3] = {{0, 0}, {c, si}, {-si, c}};
  EXPECT_NEAR(faceStretch(q, r).l2, 1.0, 1e-12);
  EXPECT_NEAR(faceStretch(q, r).linf, 1.0, 1e-12);
}

TEST(Metrics, MeshStretchIsScaleInvariantAndOneForSimilarities) {
  const test::Mesh m = test::planarGrid(6);
  const Patch patch = buildPatch(m.V, m.F);
  Eigen::Matrix2d similarity;
  similarity << 0.3, -0.4, 0.4, 0.3;  // rotation and scale 0.5
  const StretchMetrics s = stretchMetrics(patch, affineUVs(patch, similarity));
  EXPECT_NEAR(s.l2, 1.0, 1e-12);
  EXPECT_NEAR(s.linf, 1.0, 1e-12);
  EXPECT_EQ(s.flipped_faces, 0);
  // Anisotropic (3x, y): singular values of the inverse 1/3 and 1, normalized by sqrt(3).
  Eigen::Matrix2d stretch;
  stretch << 3, 0, 0, 1;
  const StretchMetrics t = stretchMetrics(patch, affineUVs(patch, stretch));
  EXPECT_NEAR(t.l2, std::sqrt((1.0 / 9 + 1) / 2) * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(t.linf, std::sqrt(3.0), 1e-12);
  for (double f : t.face_l2) EXPECT_NEAR(f, t.l2, 1e-12);
}

TEST(Metrics, AHoleTurnedInsideOutCountsItsFillFacesAsFlipped) {
  // An annulus (inner ring of 8 at radius 1, outer at radius 2): its hole is filled with a fan
  // of 8 virtual faces.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V(16, 3);
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> F(16, 3);
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / 8;
    V.row(k) << std::cos(a), std::sin(a), 0;
    V.row(8 + k) << 2 * std::cos(a), 2 * std::sin(a), 0;
    F.row(2 * k) << k, 8 + k, 8 + (k + 1) % 8;
    F.row(2 * k + 1) << k, 8 + (k + 1) % 8, (k + 1) % 8;
  }
  const Patch patch = buildPatch(V, F);
  ASSERT_EQ(patch.holes_filled, 1);
  std::vector<Eigen::Vector2d> uv = affineUVs(patch, Eigen::Matrix2d::Identity());
  EXPECT_EQ(stretchMetrics(patch, uv).flipped_faces, 0);
  EXPECT_FALSE(hasFlippedFace(patch, uv));
  // The inner ring's positions taken in reverse order: the hole's border runs the other way.
  // Counted by hand: the real faces that flip, then the fill's 8 faces on top; flipped means
  std::vector<Eigen::Vector2d> reversed = uv;
  for (int k = 0; k < 8; ++k) reversed[patch.local_vertex[k]] = uv[patch.local_vertex[(8 - k) % 8]];
  // against the side most of the area is on (metrics.h's flip rule).
  std::vector<double> twice_area;
  double total = 0;
  for (int f = 0; f < patch.real_face_count; ++f) {
    const auto& t = patch.face[f];
    const Eigen::Vector2d a = reversed[t[0]], b = reversed[t[1]], c = reversed[t[2]];
    twice_area.push_back((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    total += twice_area.back();
  }
  ASSERT_GT(total, 0);
  int real_flipped = 0;
  for (double a : twice_area) real_flipped += a <= 0;
  EXPECT_EQ(stretchMetrics(patch, reversed).flipped_faces, real_flipped + 8);
  EXPECT_TRUE(hasFlippedFace(patch, reversed));
}

TEST(Metrics, FlippedAndDegenerateFacesAreCounted) {
  const test::Mesh m = test::planarGrid(4);
  const Patch patch = buildPatch(m.V, m.F);
  std::vector<Eigen::Vector2d> uv = affineUVs(patch, Eigen::Matrix2d::Identity());
  EXPECT_EQ(stretchMetrics(patch, uv).flipped_faces, 0);
  EXPECT_FALSE(hasFlippedFace(patch, uv));
  // A mirrored layout is still one-to-one: orientation follows the majority.
  Eigen::Matrix2d mirror;
  mirror << -1, 0, 0, 1;
  EXPECT_EQ(stretchMetrics(patch, affineUVs(patch, mirror)).flipped_faces, 0);
  EXPECT_FALSE(hasFlippedFace(patch, affineUVs(patch, mirror)));
  // Pull one interior vertex across its neighbour: some of its faces fold.
  const int v = patch.local_vertex[2 * 5 + 2];
  uv[v] += Eigen::Vector2d(1.2, 0);
  const StretchMetrics folded = stretchMetrics(patch, uv);
  EXPECT_GT(folded.flipped_faces, 0);
  EXPECT_TRUE(hasFlippedFace(patch, uv));
  EXPECT_TRUE(std::isfinite(folded.l2));  // folded, but measurable (peers' maps fold)
  // The same fold in a mirrored layout: the majority's side is the other one.
  std::vector<Eigen::Vector2d> mirrored = uv;
  for (auto& p : mirrored) p.x() = -p.x();
  EXPECT_TRUE(hasFlippedFace(patch, mirrored));
  // Collapse a face to a segment: degenerate counts too.
  uv = affineUVs(patch, Eigen::Matrix2d::Identity());
  const auto& t = patch.face[0];
  uv[t[2]] = 0.5 * (uv[t[0]] + uv[t[1]]);
  EXPECT_GE(stretchMetrics(patch, uv).flipped_faces, 1);
  EXPECT_TRUE(hasFlippedFace(patch, uv));
  // A coordinate that is not a number counts as flipped.
  uv = affineUVs(patch, Eigen::Matrix2d::Identity());
  uv[v].x() = std::nan("");
  EXPECT_TRUE(hasFlippedFace(patch, uv));
}

}  // namespace
}  // namespace sdp
