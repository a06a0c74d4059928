// Boundary mappings of docs/method.md §3: circle, square, and the paper's §3 measured boundary.
// Every function returns 2D positions parallel to patch.boundary_loop, counter-clockwise.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/common/options.h"
#include "core/common/patch.h"

namespace sdp {

using Polygon = std::vector<Eigen::Vector2d>;

// Unit circle, spacing proportional to 3D chord length.
Polygon circleBoundary(const Patch& patch);

// Unit square's perimeter; corners at the boundary vertices nearest to quarter arc lengths.
// Needs at least 4 boundary vertices (returns an empty polygon otherwise).
Polygon squareBoundary(const Patch& patch);

// Distances along mesh edges from the given vertices (Dijkstra), for every vertex.
std::vector<double> edgeGraphDistances(const Patch& patch, const std::vector<int>& sources);

// Default source vertex S of the measured boundary (local index; -1 if there is no interior
// vertex). FarthestFromBoundary: the interior vertex farthest from the boundary along mesh edges.
// NearestBoundaryCentroid: the interior vertex nearest to the centroid of the boundary vertices.
int chooseSourceVertex(const Patch& patch, SourceRule rule);

struct MeasuredCounts {
  int walk_failures = 0;  // plane walks that left the patch away from their boundary vertex
  int walk_detours = 0;   // walks much longer than the edge-graph distance (sanity rule)
  // Ear apexes (boundary vertices of a single face) placed across their chord with the ear's
  // own shape instead of on the convex polygon, which would crush the ear flat.
  int ears_unfolded = 0;
};

// Straightest distance from S to boundary vertex b: the length of the intersection of the mesh
// with the plane through S and b that contains normal (the base normal at S), walked from S
// until it leaves the patch. Returns a negative value when the walk does not end at b.
double planeWalkDistance(const Patch& patch, int source, const Eigen::Vector3d& normal, int b);

// The measured boundary (paper §3, docs/method.md §3): polar angles of the virtual edges S -> b_k
// on the base plane at S, straightest distances as radii, made strictly convex, scaled to the mesh
// area.
Polygon measuredBoundary(const Patch& patch, int source, MeasuredCounts& counts);

// Pairs of boundary positions joined by an interior mesh edge (a "dividing edge"; an ear's
// third side is one). On a straight stretch of a convex boundary such an edge makes degenerate
// triangles, so the stretch must bulge visibly there.
std::vector<std::pair<int, int>> dividingEdges(const Patch& patch);

// Makes a polygon that is star-shaped around the origin strictly convex, keeping the vertex
// order: hull vertices stay, the others move onto a bulging arc between their hull neighbours,
// spaced by `spacing` (e.g. 3D boundary edge lengths; spacing[k] is the length from vertex k to
// k+1). The bulge is tiny (1e-4 of the side) unless a dividing edge lies within that side, then
// as large as convexity at the corners allows (at most 5% of the side).
Polygon makeStrictlyConvex(const Polygon& polygon, const std::vector<double>& spacing,
                           const std::vector<std::pair<int, int>>& dividing_edges = {});

// Stretch of the ears -- faces whose three corners are all on the boundary, so the boundary
// polygon alone decides their shape -- as the area-weighted L2 of docs/method.md §5 with the
// polygon scaled to the mesh's area. 0 when the patch has no ear. Lets a polygon be judged before
// any solve.
double earStretch(const Patch& patch, const Polygon& polygon);

// Signed area (positive when counter-clockwise).
double polygonArea(const Polygon& polygon);

}  // namespace sdp
