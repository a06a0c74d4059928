#include "planar_chart.h"

#include <algorithm>
#include <cmath>

#include "core/common/border.h"
#include "core/common/connectivity.h"
#include "core/common/geometry.h"
#include "core/common/metrics.h"

namespace sdp::atlas {

namespace {

// Whether the map uv of the faces F is one-to-one: as the patch pipeline's maps are checked.
bool oneToOne(const Triangles& F, const std::vector<Eigen::Vector2d>& uv) {
  const int faces = static_cast<int>(F.rows());
  // Every face on the same side (the rule the pipeline's maps are checked by) ...
  double total = 0;
  std::vector<double> area(faces);
  for (int f = 0; f < faces; ++f) {
    area[f] = signedArea(uv[F(f, 0)], uv[F(f, 1)], uv[F(f, 2)]);
    total += area[f];
  }
  const FlipRule rule(total);
  if (!(total > 0)) return false;
  for (double a : area)
    if (rule.flipped(a)) return false;
  // ... and the border simple, with the refinement's clearance (a slit a hair's breadth wide
  // would touch itself once stored).
  std::vector<BorderEdge> border;
  for (const HalfEdgeKey& key : borderHalfEdges(F, static_cast<int>(uv.size())))
    border.push_back({key.low, key.high});
  return edgesAreSimple(border, uv, borderClearance(border, uv));
}

}  // namespace

std::optional<std::vector<Eigen::Vector2d>> projectIfPlanar(const Positions& V,
                                                            const Triangles& F) {
  const int faces = static_cast<int>(F.rows());
  if (faces == 0) return std::nullopt;
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return V.row(F(f, k)).transpose(); };
  // The area-weighted mean normal (twice the area per face, summed).
  std::vector<Eigen::Vector3d> normal(faces);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int f = 0; f < faces; ++f) {
    normal[f] = (corner(f, 1) - corner(f, 0)).cross(corner(f, 2) - corner(f, 0));
    mean += normal[f];
  }
  if (!(mean.norm() > 0) || !mean.allFinite()) return std::nullopt;
  mean.normalize();
  const double least_cos = std::cos(kPlanarChartDegrees * kPi / 180);
  for (int f = 0; f < faces; ++f) {
    const double length = normal[f].norm();
    if (!(length > 0) || !(normal[f].dot(mean) >= least_cos * length)) return std::nullopt;
  }
  // An orthonormal frame (u, v, mean): faces counter-clockwise about the mean stay so in (u, v).
  const Eigen::Vector3d u = mean.unitOrthogonal(), v = mean.cross(u);
  const Eigen::Vector3d origin = V.row(0).transpose();
  std::vector<Eigen::Vector2d> uv(V.rows());
  for (int i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i).transpose() - origin;
    uv[i] = Eigen::Vector2d(p.dot(u), p.dot(v));
  }
  if (!oneToOne(F, uv)) return std::nullopt;
  return uv;
}

std::optional<std::vector<Eigen::Vector2d>> unrollIfDevelopable(const Positions& V,
                                                                const Triangles& F) {
  const int faces = static_cast<int>(F.rows()), vertices = static_cast<int>(V.rows());
  if (faces == 0) return std::nullopt;
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return V.row(F(f, k)).transpose(); };
  // Angles around each inner vertex (the border's vertices may have any).
  std::vector<double> angle_sum(vertices, 0.0);
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = corner(f, (k + 1) % 3) - corner(f, k),
                            b = corner(f, (k + 2) % 3) - corner(f, k);
      angle_sum[F(f, k)] += std::atan2(a.cross(b).norm(), a.dot(b));
    }
  // From one sort of the half-edges: the border's vertices (an edge of one face) and, across
  // each edge of two faces that run it opposite ways, the other face's half-edge.
  std::vector<char> on_border(vertices, 0);
  std::vector<int> across(3 * faces, -1);
  const std::vector<HalfEdgeKey> keys = sortedHalfEdges(F, vertices);
  forEachEdgeRun(keys, [&](size_t begin, size_t end) {
    if (end - begin == 1) on_border[keys[begin].low] = on_border[keys[begin].high] = 1;
    if (end - begin != 2) return;
    const int h = keys[begin].half_edge, g = keys[begin + 1].half_edge;
    if (F(h / 3, h % 3) == F(g / 3, g % 3)) return;  // both run it the same way
    across[h] = g, across[g] = h;
  });
  for (int v = 0; v < vertices; ++v)
    if (!on_border[v] && !(std::abs(2 * kPi - angle_sum[v]) <= kDevelopableDefect))
      return std::nullopt;
  // Face f's corner k + 2 placed left of its edge k -> k + 1, already placed, at the face's own
  // shape: the faces run counter-clockwise in the plane as they run around their normals.
  std::vector<Eigen::Vector2d> uv(vertices, Eigen::Vector2d::Zero());
  std::vector<char> placed(vertices, 0);
  auto placeThird = [&](int f, int k) {
    const Eigen::Vector3d e = corner(f, (k + 1) % 3) - corner(f, k),
                          c = corner(f, (k + 2) % 3) - corner(f, k);
    const double length = e.norm();
    const double along = c.dot(e) / length, height = e.cross(c).norm() / length;
    const Eigen::Vector2d a = uv[F(f, k)], d = (uv[F(f, (k + 1) % 3)] - a).normalized();
    uv[F(f, (k + 2) % 3)] = a + along * d + height * Eigen::Vector2d(-d.y(), d.x());
    placed[F(f, (k + 2) % 3)] = 1;
  };
  std::vector<char> laid(faces, 0);
  std::vector<int> queue = {0};
  uv[F(0, 0)] = Eigen::Vector2d::Zero();
  uv[F(0, 1)] = Eigen::Vector2d((corner(0, 1) - corner(0, 0)).norm(), 0);
  placed[F(0, 0)] = placed[F(0, 1)] = 1;
  placeThird(0, 0);
  laid[0] = 1;
  for (size_t at = 0; at < queue.size(); ++at) {
    const int f = queue[at];
    for (int k = 0; k < 3; ++k) {
      const int h = across[3 * f + k];
      if (h < 0 || laid[h / 3]) continue;
      const int g = h / 3;
      laid[g] = 1;
      queue.push_back(g);
      if (!placed[F(g, (h % 3 + 2) % 3)]) placeThird(g, h % 3);
    }
  }
  if (static_cast<int>(queue.size()) != faces ||
      std::find(placed.begin(), placed.end(), 0) != placed.end())
    return std::nullopt;
  // Every face's edges at their 3D lengths: equal edges make an equal triangle, so this bounds
  // each face's stretch either way (where the unrolling closes around a vertex, a face's last
  // corner may be off by the defects summed on the way).
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const double flat = (uv[F(f, (k + 1) % 3)] - uv[F(f, k)]).norm();
      const double real = (corner(f, (k + 1) % 3) - corner(f, k)).norm();
      if (!(flat <= kMostUnrolledEdgeRatio * real && real <= kMostUnrolledEdgeRatio * flat))
        return std::nullopt;
    }
  if (!oneToOne(F, uv)) return std::nullopt;
  return uv;
}

}  // namespace sdp::atlas
