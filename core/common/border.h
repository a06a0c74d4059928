// Whether a flat map's border is simple: its edges (the outer loop and the holes) neither cross
// nor touch, apart from neighbours at their shared vertex. The paper's measured boundary, the
// refinement's checked steps and the storage's certificate all ask it of the same sweep.
#pragma once

#include <array>
#include <vector>

#include "patch.h"

namespace sdp {

// Edges with a real face on one side only: the outer loop and the hole loops.
using BorderEdge = std::array<int, 2>;
std::vector<BorderEdge> boundaryEdges(const Patch& patch);

// No two of these edges cross or touch, apart from neighbours at their shared vertex. The
// edges come by value: they are sorted along x for the sweep. With `clearance` > 0, also false
// when two of them come closer than that.
bool edgesAreSimple(std::vector<BorderEdge> edges, const LocalUVs& uv, double clearance = 0);

// The end vertices of the edges that cross or touch another (not a neighbour at their shared
// vertex), sorted, each once.
std::vector<int> verticesOfMeetingEdges(std::vector<BorderEdge> edges, const LocalUVs& uv);

// The clearance the refinement keeps between non-adjacent border edges: kBorderClearance times
// the border's bounding-box diagonal. Without it a step may stop a hair's breadth from closing a
// notch (1e-8 of the atlas on a 1.4M-face scan), and the stored values' rounding then makes the
// border touch itself; 1e-4 of the chart is far below an edge and far above any rounding of a
// chart that is not tiny in its texture.
constexpr double kBorderClearance = 1e-4;
double borderClearance(const std::vector<BorderEdge>& edges, const LocalUVs& uv);

// True when no two edges that bound the real faces (outer loop and holes) cross or touch,
// apart from neighbours meeting at their shared vertex.
bool boundaryIsSimple(const Patch& patch, const LocalUVs& uv);

}  // namespace sdp
