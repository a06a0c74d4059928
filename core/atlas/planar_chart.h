// Flat and developable faces laid flat without the patch pipeline. A face set whose faces all face
// the same way (within kPlanarChartDegrees of their mean normal) is projected onto the plane of
// that normal. On a flat face of a CAD part this is an isometry, sliver by sliver (a
// fan-triangulated face's needles keep their shape, where a refinement that weighs faces by area
// leaves them stretched), at a fraction of the patch pipeline's cost; holes need no filling.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/common/layout.h"

namespace sdp::atlas {

// The largest angle between a face's normal and the faces' mean normal for a projection: the
// projection shortens a face by at most its cosine (1/cos 2 degrees = 1.0006 in L-infinity).
constexpr double kPlanarChartDegrees = 2.0;

// The projected texture coordinates, one per vertex of V (counter-clockwise where the faces are),
// when every face is within kPlanarChartDegrees of the mean normal and the projection is
// one-to-one: no face flipped or degenerate, and no two border edges crossing or coming closer
// than the refinement's clearance (core/common/border.h). Else nothing (the patch pipeline then
// flattens the faces). F indexes V; every vertex of V is used.
std::optional<std::vector<Eigen::Vector2d>> projectIfPlanar(const Positions& V, const Triangles& F);

// The largest angle defect (2 pi against the angles around it, either way) at an inner vertex of
// a face set unrolled, and how far any face's edge may then differ from its 3D length: a
// developable surface (a drilled hole's wall, a shaft, a cone's side away from its apex, a bent
// sheet) has no defect, and is laid flat to within 0.1 %.
constexpr double kDevelopableDefect = 1e-4;
constexpr double kMostUnrolledEdgeRatio = 1.001;

// The texture coordinates of a developable disk unrolled face by face (each face laid beside the
// one before across their shared edge, at its own edge lengths), one per vertex of V
// (counter-clockwise where the faces are): when every inner vertex's defect is within
// kDevelopableDefect, every face is reached across edges the faces run opposite ways along, every
// face's edges keep their 3D lengths within kMostUnrolledEdgeRatio (a triangle's edges fix its
// shape; where the unrolling closes around a vertex the defects add up) and the map is one-to-one
// as projectIfPlanar checks it (a cone of more than a turn would overlap itself). Else nothing.
// F indexes V, a manifold disk wound one way (an atlas chart's faces); every vertex of V is used.
std::optional<std::vector<Eigen::Vector2d>> unrollIfDevelopable(const Positions& V,
                                                                const Triangles& F);

}  // namespace sdp::atlas
