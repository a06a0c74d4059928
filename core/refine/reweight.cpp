#include "reweight.h"

#include <algorithm>
#include <cmath>

namespace sdp {

// Yoshizawa-Belyaev-Seidel: damp the pull of neighbours that are stretched, a_ij / sigma_j^eta,
// then renormalize each row. Weights stay positive, so the map stays one-to-one.
void reweightByStretch(const Patch& patch, const std::vector<double>& vertex_l2, double eta,
                       std::vector<double>& weights) {
  for (int v = 0; v < patch.vertexCount(); ++v) {
    if (patch.on_boundary[v]) continue;
    double sum = 0;
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) {
      const double sigma = std::max(vertex_l2[patch.ring_vertex[k]], 1e-6);
      weights[k] /= std::pow(sigma, eta);
      sum += weights[k];
    }
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) weights[k] /= sum;
  }
}

}  // namespace sdp
