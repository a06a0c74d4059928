#include "planar_chart.h"

#include <algorithm>
#include <cmath>

#include "core/common/border.h"
#include "core/common/connectivity.h"
#include "core/common/geometry.h"
#include "core/common/metrics.h"

namespace sdp::atlas {

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
  // One-to-one: every face on the same side (the rule the pipeline's maps are checked by) ...
  double total = 0;
  std::vector<double> area(faces);
  for (int f = 0; f < faces; ++f) {
    area[f] = signedArea(uv[F(f, 0)], uv[F(f, 1)], uv[F(f, 2)]);
    total += area[f];
  }
  const FlipRule rule(total);
  if (!(total > 0)) return std::nullopt;
  for (double a : area)
    if (rule.flipped(a)) return std::nullopt;
  // ... and the border simple, with the refinement's clearance (a slit a hair's breadth wide
  // would touch itself once stored).
  std::vector<BorderEdge> border;
  for (const HalfEdgeKey& key : borderHalfEdges(F, static_cast<int>(V.rows())))
    border.push_back({key.low, key.high});
  if (!edgesAreSimple(border, uv, borderClearance(border, uv))) return std::nullopt;
  return uv;
}

}  // namespace sdp::atlas
