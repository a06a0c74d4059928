#include "convex_cut.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <utility>

#include "core/common/connectivity.h"
#include "core/common/geometry.h"
#include "pack.h"

namespace sdp::atlas {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// The area of a convex hull (pack.h's), fanned from its first corner.
double fanArea(const std::vector<Eigen::Vector2d>& hull) {
  double area = 0;
  for (size_t i = 2; i < hull.size(); ++i) area += 0.5 * cross(hull[0], hull[i - 1], hull[i]);
  return area;
}

// The area of the convex hull of the points.
double hullArea(std::vector<Eigen::Vector2d> points) {
  return fanArea(convexHull(std::move(points)));
}

double polygonArea(const std::vector<Eigen::Vector2d>& p) {
  double area = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& a = p[i];
    const Eigen::Vector2d& b = p[(i + 1) % p.size()];
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  return area;
}

// The side {x : side * (normal . x - offset) <= 0} of the polygon (Sutherland-Hodgman), point by
// point to `visit`: for a polygon that is not convex the pieces come joined along the line, which
// leaves their area and their hull right.
template <class Visit>
void clip(const std::vector<Eigen::Vector2d>& polygon, const std::vector<double>& height,
          double offset, double side, Visit visit) {
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    const double a = side * (height[i] - offset), b = side * (height[j] - offset);
    if (a <= 0) visit(polygon[i], true);
    if ((a < 0 && b > 0) || (a > 0 && b < 0))
      visit(Eigen::Vector2d(polygon[i] + (polygon[j] - polygon[i]) * (a / (a - b))), false);
  }
}

// polygonArea of the clipped side, summed in the same order, without building it (most lines
// tried end at the areas).
double clippedArea(const std::vector<Eigen::Vector2d>& polygon, const std::vector<double>& height,
                   double offset, double side) {
  double area = 0;
  Eigen::Vector2d first, last;
  bool any = false;
  clip(polygon, height, offset, side, [&](const Eigen::Vector2d& p, bool) {
    if (any) area += 0.5 * (last.x() * p.y() - last.y() * p.x());
    if (!any) first = p, any = true;
    last = p;
  });
  if (any) area += 0.5 * (last.x() * first.y() - last.y() * first.x());
  return area;
}

// hullArea of the clipped side from the polygon's corners in xThenY order (`sorted`): the side's
// corners are taken from it in that order and the few points on the line merged in, so no hull
// sorts all its points again.
double clippedHullArea(const std::vector<Eigen::Vector2d>& polygon, const std::vector<int>& sorted,
                       const std::vector<double>& height, double offset, double side) {
  std::vector<Eigen::Vector2d> on_line;
  clip(polygon, height, offset, side, [&](const Eigen::Vector2d& p, bool corner) {
    if (!corner) on_line.push_back(p);
  });
  std::sort(on_line.begin(), on_line.end(), xThenY);
  std::vector<Eigen::Vector2d> corners, points;
  corners.reserve(sorted.size());
  for (int i : sorted)
    if (side * (height[i] - offset) <= 0) corners.push_back(polygon[i]);
  points.reserve(corners.size() + on_line.size());
  std::merge(corners.begin(), corners.end(), on_line.begin(), on_line.end(),
             std::back_inserter(points), xThenY);
  return fanArea(convexHullOfSorted(std::move(points)));
}

}  // namespace

std::vector<std::pair<int, int>> borderEdges(const std::vector<std::array<int, 3>>& triangles) {
  Triangles F(triangles.size(), 3);
  int vertices = 0;
  for (size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      F(i, k) = triangles[i][k];
      vertices = std::max(vertices, triangles[i][k] + 1);
    }
  std::vector<std::pair<int, int>> edges;
  for (const HalfEdgeKey& key : borderHalfEdges(F, vertices)) {
    const int f = key.half_edge / 3, k = key.half_edge % 3;
    edges.emplace_back(F(f, k), F(f, (k + 1) % 3));
  }
  return edges;
}

std::vector<int> boundaryLoop(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<std::pair<int, int>> next = borderEdges(triangles);
  if (next.empty()) return {};
  std::sort(next.begin(), next.end());
  for (size_t i = 1; i < next.size(); ++i)
    if (next[i].first == next[i - 1].first) return {};  // two boundary edges leave a vertex
  const size_t edges = next.size();
  std::vector<int> loop;
  for (int v = next.front().first;;) {
    loop.push_back(v);
    const auto it = std::lower_bound(next.begin(), next.end(), std::make_pair(v, INT_MIN));
    if (it == next.end() || it->first != v || loop.size() > edges) return {};
    v = it->second;
    if (v == loop.front()) break;
  }
  if (loop.size() != edges) return {};
  return loop;
}

std::optional<ConvexCut> bestConvexCut(const std::vector<Eigen::Vector2d>& uv,
                                       const std::vector<std::array<int, 3>>& triangles,
                                       double min_share) {
  std::vector<Eigen::Vector2d> polygon;
  for (int v : boundaryLoop(triangles)) polygon.push_back(uv[v]);
  if (polygon.size() < 4) return std::nullopt;
  const double area = polygonArea(polygon);
  const double hull = hullArea(polygon);
  if (!(area > 0) || !(hull > area)) return std::nullopt;
  std::vector<int> sorted(polygon.size());
  std::iota(sorted.begin(), sorted.end(), 0);
  std::sort(sorted.begin(), sorted.end(),
            [&](int a, int b) { return xThenY(polygon[a], polygon[b]); });
  constexpr int kDirections = 16, kOffsets = 32;
  std::optional<ConvexCut> best;
  double best_score = 0;
  std::vector<double> height(polygon.size());
  for (int d = 0; d < kDirections; ++d) {
    const double angle = kPi * d / kDirections;  // a line and its reverse are the same cut
    const Eigen::Vector2d normal(std::cos(angle), std::sin(angle));
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (size_t i = 0; i < polygon.size(); ++i) {
      height[i] = normal.dot(polygon[i]);
      low = std::min(low, height[i]), high = std::max(high, height[i]);
    }
    for (int o = 1; o < kOffsets; ++o) {
      const double offset = low + (high - low) * o / kOffsets;
      // The line's length inside the chart: its crossings with the border, paired in order.
      std::vector<double> along;
      const Eigen::Vector2d tangent(-normal.y(), normal.x());
      for (size_t i = 0; i < polygon.size(); ++i) {
        const size_t j = (i + 1) % polygon.size();
        const double a = height[i] - offset, b = height[j] - offset;
        if ((a < 0) != (b < 0))
          along.push_back(tangent.dot(polygon[i] + (polygon[j] - polygon[i]) * (a / (a - b))));
      }
      // A line crossing the border more than twice would cut off several pieces: one new chart
      // per cut keeps the count down.
      if (along.size() != 2) continue;
      const double length = std::abs(along[1] - along[0]);
      if (!(length > 0)) continue;
      const double below_area = clippedArea(polygon, height, offset, 1);
      const double above_area = clippedArea(polygon, height, offset, -1);
      if (below_area < min_share * area || above_area < min_share * area) continue;
      // Each side's hull holds at least its own area, so the gain is at most the hull minus
      // both areas: a line that cannot beat the best even so needs no hulls (the costly part,
      // a sort each). The slack keeps rounding from skipping a line that would win.
      if ((hull - below_area - above_area) / length < best_score * (1 - 1e-9)) continue;
      const double gain = hull - clippedHullArea(polygon, sorted, height, offset, 1) -
                          clippedHullArea(polygon, sorted, height, offset, -1);
      if (!(gain > 0)) continue;
      const double score = gain / length;
      if (score > best_score) {
        best_score = score;
        best = ConvexCut{normal, offset, gain, length};
      }
    }
  }
  return best;
}

ConvexCut middleCut(const std::vector<Eigen::Vector2d>& uv, double& extent) {
  const Eigen::Vector2d axis = smallestBoxRotation(uv).row(0).transpose();
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const Eigen::Vector2d& p : uv)
    low = std::min(low, axis.dot(p)), high = std::max(high, axis.dot(p));
  extent = uv.empty() ? 0 : high - low;
  ConvexCut cut;
  cut.normal = axis;
  cut.offset = 0.5 * (low + high);
  return cut;
}

}  // namespace sdp::atlas
