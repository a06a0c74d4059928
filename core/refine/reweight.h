// The first refinement (docs/method.md §4): the paper's weights reweighted by
// the stretch each vertex's neighbours show, and the map solved again on the same boundary. The
// loop that repeats it within the work budget is the pipeline's (core/parameterize.cpp,
// Pipeline::reweight).
#pragma once

#include <vector>

#include "core/common/patch.h"

namespace sdp {

// Yoshizawa-Belyaev-Seidel: damp the pull of neighbours that are stretched, a_ij / sigma_j^eta,
// then renormalize each row. Weights stay positive, so the map stays one-to-one.
void reweightByStretch(const Patch& patch, const std::vector<double>& vertex_l2, double eta,
                       std::vector<double>& weights);

}  // namespace sdp
