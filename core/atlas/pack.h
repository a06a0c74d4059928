// Packing charts into the unit square at one scale (docs/method.md §7): each chart is turned to
// its smallest bounding rectangle, then charts, largest first, drop onto a skyline of texel
// columns (a Tetris-like packer, as in Lévy et al. 2002) at their lowest free spot (lowest top
// edge, then lowest, then leftmost), trying four quarter turns (never a mirror), holes below the
// skyline included. "Largest" is tried in four senses (area, long side, short side, bounding
// rectangle) and the order that packs at the largest scale is kept. A chart is placed by the cells
// it touches (raster.h, conservative), grown by gutter - 1 cells, so no covered pixel of one chart
// comes within gutter - 1 pixels of another's, whatever the rounding of the stored values. The
// scale is the largest that fits, found by bisection.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

namespace sdp::atlas {

// One chart in its own frame (e.g. 3D units): positions and triangles (indices into uv).
struct ChartShape {
  std::vector<Eigen::Vector2d> uv;
  std::vector<std::array<int, 3>> triangles;
};

// A chart's place: uv_packed = (rotation * uv * texels_per_unit + offset) / texture_size.
struct Placement {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // texels
};

struct Packing {
  double texels_per_unit = 0;
  std::vector<Placement> placements;  // per chart
  int attempts = 0;                   // scales tried
  Eigen::Vector2d apply(int chart, const Eigen::Vector2d& uv, int texture_size) const {
    const Placement& p = placements[chart];
    return (p.rotation * uv * texels_per_unit + p.offset) / texture_size;
  }
};

struct PackOptions {
  int texture_size = 2048;
  int gutter = 2;
  // Extra cell margin around each triangle, in texels: room for the stored values' rounding.
  double margin = 1e-3;
  // Largest scale tried, relative to the one where the charts' area fills the square: a scale
  // is accepted only below this.
  double shrink = 1.0;
  // Called on the calling thread as charts are placed: `done`, from 0 to 1, of the `attempt`-th
  // pack (from 0) of the scale search; may be empty. Half of it counts charts, half weighs each
  // by the square root of its texture coordinates: a chart's search costs a part that follows
  // its border and a part that does not, and the large charts come first (by count alone the
  // bar waited 3 s at the start of a pack of 4735 charts, by border alone at its end).
  std::function<void(double done, int attempt)> progress;
};

// The area the triangles cover in the plane (each counted positive).
double uvArea(const std::vector<Eigen::Vector2d>& uv,
              const std::vector<std::array<int, 3>>& triangles);

// The convex hull of the points, counter-clockwise without repeats (Andrew's monotone chain).
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points);
// The same of points already in xThenY order, without the sort.
std::vector<Eigen::Vector2d> convexHullOfSorted(std::vector<Eigen::Vector2d> points);
// The order the hull sorts its points in: by x, then by y.
bool xThenY(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// The rotation that lays the chart's smallest bounding rectangle (one side on a hull edge) with
// its long side along x.
Eigen::Matrix2d smallestBoxRotation(const std::vector<Eigen::Vector2d>& uv);

// Throws ParameterizationError when the charts cannot fit at any scale above a texel per chart
// (more charts than the texture can hold).
Packing packCharts(const std::vector<ChartShape>& charts, const PackOptions& options);

}  // namespace sdp::atlas
