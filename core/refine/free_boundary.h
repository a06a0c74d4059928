// Beyond the paper: refinement with the boundary let go. A fixed convex boundary caps what any
// reweighting can do: faces with all three corners on the boundary (the ears and fins of
// camel_b) are shaped by the polygon alone and stay crushed. Here local/global
// as-rigid-as-possible steps (Liu, Zhang, Xu, Gotsman, Gortler 2008) start from the one-to-one
// fixed-boundary map and move every vertex, boundary included, towards the 3D shape of its
// faces. Each step is checked before it is taken: a step that would flip or collapse a face or
// make the boundary cross itself is halved until it does neither, or dropped. A map with no
// flipped face whose boundary curves do not cross is one-to-one, so the guarantee holds.
#pragma once

#include <array>
#include <vector>

#include "core/common/border.h"
#include "core/common/metrics.h"
#include "core/common/options.h"
#include "core/common/patch.h"
#include "core/common/progress.h"
#include "core/paper/solve.h"
#include "refine_budget.h"

namespace sdp {

struct FreeBoundaryCounts {
  int steps_taken = 0;      // steps applied (in full or shortened)
  int steps_shortened = 0;  // ... of them shortened to avoid a fold or a boundary crossing
  bool stopped = false;     // a step could not be taken at any length: the refinement stopped
};

// Up to `steps` steps from `uv` (one-to-one, with its metrics in `metrics`). Returns the map with
// the lowest L2 stretch seen (the start if no step lowers it) and its metrics in `metrics`.
// Virtual hole-fill vertices keep their start positions; they are not part of the user's mesh.
// `progress` is told of each step (Stage::FreeBoundary) and may cancel.
LocalUVs relaxWithFreeBoundary(const Patch& patch, const LocalUVs& uv, int steps,
                               StretchMetrics& metrics, FreeBoundaryCounts& counts,
                               const Progress& progress = Progress(),
                               const RefineBudget& budget = {});

// Face f laid flat isometrically: corner 0 at the origin, corner 1 on the positive x axis,
// corner 2 above it (all at the origin when edge 0 has no length).
std::array<Eigen::Vector2d, 3> flatTriangle(const Patch& patch, int f);

}  // namespace sdp
