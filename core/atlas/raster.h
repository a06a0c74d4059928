// Triangles on a texel grid, two ways: every cell a triangle touches (conservative, for packing:
// what a chart may cover once stored), and the pixels whose centre it covers by a top-left fill
// rule (what a renderer draws, for the checks: two triangles sharing an edge never both cover a
// pixel on it). Texel (x, y) is the square [x, x+1] x [y, y+1]; its centre is (x+0.5, y+0.5).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdp::atlas {

// Calls visit(y, x0, x1) for every row y of the grid [0, width) x [0, height) that the
// triangle, grown by `margin` texels, touches, with the span [x0, x1] of cells it touches there:
// the triangle's extent within the row's slab (itself grown by the margin), so each row is one
// span.
template <class VisitSpan>
void conservativeSpans(const Eigen::Vector2d p[3], double margin, int width, int height,
                       VisitSpan&& visit) {
  const double y_low = std::min({p[0].y(), p[1].y(), p[2].y()});
  const double y_high = std::max({p[0].y(), p[1].y(), p[2].y()});
  const int row0 = std::max(0, static_cast<int>(std::floor(y_low - margin)));
  const int row1 = std::min(height - 1, static_cast<int>(std::floor(y_high + margin)));
  for (int y = row0; y <= row1; ++y) {
    const double s0 = y - margin, s1 = y + 1 + margin;
    double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
    auto take = [&](double x) { x_low = std::min(x_low, x), x_high = std::max(x_high, x); };
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& a = p[k];
      const Eigen::Vector2d& b = p[(k + 1) % 3];
      if (a.y() >= s0 && a.y() <= s1) take(a.x());
      // Where the edge crosses the slab's two sides.
      for (const double line : {s0, s1})
        if ((a.y() - line) * (b.y() - line) < 0)
          take(a.x() + (b.x() - a.x()) * (line - a.y()) / (b.y() - a.y()));
    }
    if (!(x_low <= x_high)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(x_low - margin)));
    const int x1 = std::min(width - 1, static_cast<int>(std::floor(x_high + margin)));
    if (x0 <= x1) visit(y, x0, x1);
  }
}

// conservativeSpans of the segment ab (the triangle a, b, b), with the same arithmetic: the
// packer rasters a chart's border edge by edge, and a third of the work went to the degenerate
// triangle's empty edges.
template <class VisitSpan>
void conservativeSegmentSpans(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double margin,
                              int width, int height, VisitSpan&& visit) {
  const int row0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - margin)));
  const int row1 =
      std::min(height - 1, static_cast<int>(std::floor(std::max(a.y(), b.y()) + margin)));
  for (int y = row0; y <= row1; ++y) {
    const double s0 = y - margin, s1 = y + 1 + margin;
    double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
    auto take = [&](double x) { x_low = std::min(x_low, x), x_high = std::max(x_high, x); };
    if (a.y() >= s0 && a.y() <= s1) take(a.x());
    if (b.y() >= s0 && b.y() <= s1) take(b.x());
    for (const double line : {s0, s1})
      if ((a.y() - line) * (b.y() - line) < 0) {
        take(a.x() + (b.x() - a.x()) * (line - a.y()) / (b.y() - a.y()));
        take(b.x() + (a.x() - b.x()) * (line - b.y()) / (a.y() - b.y()));
      }
    if (!(x_low <= x_high)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(x_low - margin)));
    const int x1 = std::min(width - 1, static_cast<int>(std::floor(x_high + margin)));
    if (x0 <= x1) visit(y, x0, x1);
  }
}

// Calls visit(x, y) for every cell of the grid that the triangle, grown by `margin` texels,
// touches (conservativeSpans, cell by cell).
template <class Visit>
void conservativeCells(const Eigen::Vector2d p[3], double margin, int width, int height,
                       Visit&& visit) {
  conservativeSpans(p, margin, width, height, [&](int y, int x0, int x1) {
    for (int x = x0; x <= x1; ++x) visit(x, y);
  });
}

// Calls visit(y, x0, x1) for each row of [row_begin, row_end) with the pixels x0..x1 of
// [0, width) whose centre the triangle covers, by the top-left rule (either winding; zero-area
// triangles cover nothing). A row's covered pixels are always one run.
template <class VisitSpan>
void coveredSpansInRows(const Eigen::Vector2d q[3], int width, int row_begin, int row_end,
                        VisitSpan&& visit) {
  Eigen::Vector2d p[3] = {q[0], q[1], q[2]};
  double twice_area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
  if (!(twice_area != 0) || !std::isfinite(twice_area)) return;
  if (twice_area < 0) std::swap(p[1], p[2]);  // counter-clockwise from here on
  const int x0 =
      std::max(0, static_cast<int>(std::ceil(std::min({p[0].x(), p[1].x(), p[2].x()}) - 0.5)));
  const int x1 = std::min(
      width - 1, static_cast<int>(std::floor(std::max({p[0].x(), p[1].x(), p[2].x()}) - 0.5)));
  const int y0 = std::max(
      row_begin, static_cast<int>(std::ceil(std::min({p[0].y(), p[1].y(), p[2].y()}) - 0.5)));
  const int y1 = std::min(
      row_end - 1, static_cast<int>(std::floor(std::max({p[0].y(), p[1].y(), p[2].y()}) - 0.5)));
  // An edge a -> b owns the centres exactly on it when it runs up, or runs left along a row:
  // the edge shared by two triangles runs the other way in the other, which then does not.
  // Each edge's side test is evaluated from its lower endpoint (by y, then x) and negated when
  // the edge runs the other way, so the two triangles sharing an edge compute exactly opposite
  // values: evaluated from each triangle's own corner, rounding could put a centre on the edge
  // inside both (a split quad's diagonal through pixel centres was covered twice).
  bool owns[3], reversed[3];
  Eigen::Vector2d origin[3], direction[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& a = p[k];
    const Eigen::Vector2d& b = p[(k + 1) % 3];
    const Eigen::Vector2d e = b - a;
    owns[k] = e.y() > 0 || (e.y() == 0 && e.x() < 0);
    reversed[k] = b.y() < a.y() || (b.y() == a.y() && b.x() < a.x());
    origin[k] = reversed[k] ? b : a;
    direction[k] = reversed[k] ? Eigen::Vector2d(a - b) : e;
  }
  // Only the pixels near the triangle's extent along each row's centre line are tested, which
  // halves the work on large triangles; the margin keeps every pixel the exact test could take.
  double extent = 0;
  for (const Eigen::Vector2d& corner : p) extent = std::max(extent, corner.cwiseAbs().maxCoeff());
  const double margin = 2 + 1e-7 * extent;
  for (int y = y0; y <= y1; ++y) {
    const double centre_y = y + 0.5;
    double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& a = p[k];
      const Eigen::Vector2d& b = p[(k + 1) % 3];
      if (std::min(a.y(), b.y()) > centre_y || std::max(a.y(), b.y()) < centre_y) continue;
      const double x =
          a.y() == b.y() ? a.x() : a.x() + (b.x() - a.x()) * (centre_y - a.y()) / (b.y() - a.y());
      x_low = std::min({x_low, x, a.y() == b.y() ? b.x() : x});
      x_high = std::max({x_high, x, a.y() == b.y() ? b.x() : x});
    }
    int row_x0 = x0, row_x1 = x1;
    if (x_low <= x_high) {
      auto column = [&](double x) { return static_cast<int>(std::clamp<double>(x, -1, width)); };
      row_x0 = std::max(x0, column(std::floor(x_low - 0.5 - margin)));
      row_x1 = std::min(x1, column(std::ceil(x_high - 0.5 + margin)));
    }
    auto inside = [&](int x) {
      const Eigen::Vector2d c(x + 0.5, centre_y);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& a = origin[k];
        const Eigen::Vector2d& e = direction[k];
        double side = e.x() * (c.y() - a.y()) - e.y() * (c.x() - a.x());
        if (reversed[k]) side = -side;
        if (!(side > 0 || (side == 0 && owns[k]))) return false;
      }
      return true;
    };
    // Along a row each side value is monotone in x, also as rounded (a difference and a product
    // by a constant), so each edge keeps a half-line of centres and the triangle an interval:
    // only its ends are searched, the pixels between are inside without a test.
    int first = row_x0;
    while (first <= row_x1 && !inside(first)) ++first;
    if (first > row_x1) continue;
    int last = row_x1;
    while (last > first && !inside(last)) --last;
    visit(y, first, last);
  }
}

// Calls visit(x, y) for every pixel of coveredSpansInRows.
template <class Visit>
void coveredPixelsInRows(const Eigen::Vector2d q[3], int width, int row_begin, int row_end,
                         Visit&& visit) {
  coveredSpansInRows(q, width, row_begin, row_end, [&](int y, int x0, int x1) {
    for (int x = x0; x <= x1; ++x) visit(x, y);
  });
}

// The pixels of [0, width) x [0, height) whose centre the triangle covers (above).
template <class Visit>
void coveredPixels(const Eigen::Vector2d q[3], int width, int height, Visit&& visit) {
  coveredPixelsInRows(q, width, 0, height, visit);
}

}  // namespace sdp::atlas
