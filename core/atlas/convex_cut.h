// Straight cuts that make a flattened chart more convex (docs/method.md §7). The packer places
// charts by the texels they cover, so a chart with long arms or deep bays leaves the room
// between them empty; cutting such a chart along a straight line in its plane, where the line
// crosses a narrow neck, turns one poorly packing chart into two that pack closer, for a short
// new seam (as Box Cutter, Limper et al. 2018, does with bounding boxes).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <utility>
#include <vector>

namespace sdp::atlas {

// The line {x : normal . x = offset} through a chart, and what cutting along it does.
struct ConvexCut {
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  double offset = 0;
  double hull_gain = 0;  // convex hull area before minus the two sides' hull areas after
  double length = 0;     // length of the line inside the chart, in the plane
};

// The chart's border half-edges (from, to), as the faces run: those no other triangle has the
// other way. Every loop of the border (holes too), in no particular order.
std::vector<std::pair<int, int>> borderEdges(const std::vector<std::array<int, 3>>& triangles);

// The chart's boundary as one loop of vertex indices, as the faces run; empty when the
// triangles' boundary is not one loop (not a disk).
std::vector<int> boundaryLoop(const std::vector<std::array<int, 3>>& triangles);

// The straight cut of the chart (positions `uv`, triangles into them; a disk, wound
// counter-clockwise) with the most hull area removed per length of cut, among lines in 16
// directions at 32 offsets each that cross the border twice (one new piece) and leave at least
// `min_share` of the chart's area on either side; none when no line removes any. Works on the
// chart's boundary polygon only, so the cost follows the border's length, not the number of faces.
std::optional<ConvexCut> bestConvexCut(const std::vector<Eigen::Vector2d>& uv,
                                       const std::vector<std::array<int, 3>>& triangles,
                                       double min_share);

// The line across the long side of the chart's smallest bounding rectangle, at its middle; the
// long side's length goes to `extent`. For a chart too long for the texture: it would set the
// scale of the whole atlas.
ConvexCut middleCut(const std::vector<Eigen::Vector2d>& uv, double& extent);

}  // namespace sdp::atlas
