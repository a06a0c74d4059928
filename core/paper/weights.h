// The five weight schemes of docs/method.md §2: convex combination weights a_ij of eq. (1), one row
// per interior vertex, each row non-negative and summing to 1.
#pragma once

#include <functional>
#include <vector>

#include "core/common/options.h"
#include "core/common/patch.h"
#include "straightest.h"

namespace sdp {

struct WeightCounts {
  int straightest_to_ltd = 0;  // neighbours whose cutting plane crossed no far-side edge
  int degenerate_rings = 0;    // interior vertices given uniform weights (degenerate 1-ring)
};

// Weights of one interior vertex for its ring neighbours (w has ring.size() entries). Returns
// false (and leaves w unspecified) when the ring is degenerate for this scheme.
bool ringWeights(const Ring& ring, WeightScheme scheme, double* w, int& straightest_to_ltd);

// All interior rows, parallel to patch.ring_vertex (boundary vertices' entries are 0). Degenerate
// rings fall back to uniform weights, so every row is valid; the fallbacks are counted.
// `alongside`, when given, runs on the calling thread while the other cores start on the
// weights (the pipeline measures the boundary meanwhile).
std::vector<double> computeWeights(const Patch& patch, WeightScheme scheme, WeightCounts& counts,
                                   const std::function<void()>& alongside = {});

// Copies vertex v's 1-ring out of the patch.
void gatherRing(const Patch& patch, int v, Ring& ring);

}  // namespace sdp
