#include "weights.h"

#include "core/common/geometry.h"
#include "core/common/parallel.h"

#include <cmath>

namespace sdp {
namespace {

void uniformWeights(int n, double* w) {
  for (int k = 0; k < n; ++k) w[k] = 1.0 / n;
}

// Floater 1997: geodesic polar map of the ring; for each neighbour the ray from p_j through the
// origin meets a segment (p_a, p_b); average the barycentric coordinates of the origin.
bool floaterWeights(const Ring& ring, double* w) {
  const int n = ring.size();
  std::vector<double> phi(n + 1, 0.0);
  std::vector<Eigen::Vector2d> p(n);
  for (int k = 0; k < n; ++k) phi[k + 1] = phi[k] + ring.angle[k] * 2 * kPi / ring.total_angle;
  for (int k = 0; k < n; ++k)
    p[k] = (ring.neighbour[k] - ring.center).norm() *
           Eigen::Vector2d(std::cos(phi[k]), std::sin(phi[k]));
  for (int j = 0; j < n; ++j) {
    double opposite = phi[j] + kPi;
    if (opposite >= 2 * kPi) opposite -= 2 * kPi;
    int a = 0;
    while (a < n - 1 && !(opposite >= phi[a] && opposite < phi[a + 1])) ++a;
    const int b = (a + 1) % n;
    if (a == j || b == j) return false;  // a scaled angle of at least pi: no convex combination
    // Barycentric coordinates of the origin in triangle (p_j, p_a, p_b) via signed areas.
    const double total = cross2(p[a] - p[j], p[b] - p[j]);
    if (!(std::abs(total) > 0)) return false;
    const double lj = cross2(p[a], p[b]) / total;
    const double la = cross2(p[b], p[j]) / total;
    const double lb = cross2(p[j], p[a]) / total;
    w[j] += std::max(lj, 0.0);
    w[a] += std::max(la, 0.0);
    w[b] += std::max(lb, 0.0);
  }
  return true;
}

// Floater 2003 mean value coordinates.
void meanValueWeights(const Ring& ring, double* w) {
  const int n = ring.size();
  for (int j = 0; j < n; ++j) {
    const double before = ring.angle[(j + n - 1) % n], after = ring.angle[j];
    w[j] = (std::tan(before / 2) + std::tan(after / 2)) / (ring.neighbour[j] - ring.center).norm();
  }
}

bool normalizeRow(int n, double* w) {
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(w[k]) || w[k] < 0) return false;
    sum += w[k];
  }
  if (!(sum > 0) || !std::isfinite(sum)) return false;
  for (int k = 0; k < n; ++k) w[k] /= sum;
  return true;
}

}  // namespace

namespace weight_schemes {

// The paper's scheme: each neighbour's straightest line through the centre leaves the ring
// where the cutting plane meets the far side; where it meets none, the LTD direction (counted).
bool straightest(const Ring& ring, double* w, int& to_ltd) {
  const Eigen::Vector3d normal = baseNormal(ring);
  for (int j = 0; j < ring.size(); ++j) {
    RingExit exit;
    if (!cuttingPlaneExit(ring, normal, j, exit)) {
      exit = equalAngleExit(ring, j);
      ++to_ltd;
    }
    addSegmentWeights(ring, j, exit, w);
  }
  return true;
}

bool ltd(const Ring& ring, double* w, int&) {
  for (int j = 0; j < ring.size(); ++j) addSegmentWeights(ring, j, equalAngleExit(ring, j), w);
  return true;
}

bool floater(const Ring& ring, double* w, int&) {
  return floaterWeights(ring, w);
}

bool meanValue(const Ring& ring, double* w, int&) {
  meanValueWeights(ring, w);
  return true;
}

// Equal raw weights: normalized, each is exactly 1 / n.
bool uniform(const Ring& ring, double* w, int&) {
  for (int k = 0; k < ring.size(); ++k) w[k] = 1;
  return true;
}

}  // namespace weight_schemes

bool ringWeights(const Ring& ring, WeightScheme scheme, double* w, int& straightest_to_ltd) {
  const int n = ring.size();
  for (int k = 0; k < n; ++k) w[k] = 0;
  return kWeightSchemes[static_cast<size_t>(scheme)].weights(ring, w, straightest_to_ltd) &&
         normalizeRow(n, w);
}

void gatherRing(const Patch& patch, int v, Ring& ring) {
  ring.center = patch.position[v];
  ring.neighbour.clear();
  for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k)
    ring.neighbour.push_back(patch.position[patch.ring_vertex[k]]);
}

std::vector<double> computeWeights(const Patch& patch, WeightScheme scheme, WeightCounts& counts,
                                   const std::function<void()>& alongside) {
  std::vector<double> weights(patch.ring_vertex.size(), 0.0);
  const int n = patch.vertexCount();
  std::vector<WeightCounts> per_worker(parallelWorkers());
  const WeightSchemeRow& row = kWeightSchemes[static_cast<size_t>(scheme)];
  auto rows = [&](int begin, int end, int worker) {
    Ring ring;
    WeightCounts& local = per_worker[worker];
    for (int v = begin; v < end; ++v) {
      if (patch.on_boundary[v]) continue;
      gatherRing(patch, v, ring);
      double* w = &weights[patch.ring_begin[v]];
      int vertex_to_ltd = 0;
      const bool ok =
          (!row.uses_angles || prepareRing(ring)) && ringWeights(ring, scheme, w, vertex_to_ltd);
      if (ok) {
        local.straightest_to_ltd += vertex_to_ltd;
      } else {
        uniformWeights(ring.size(), w);
        ++local.degenerate_rings;
      }
    }
  };
  if (alongside)
    parallelForAlongside(n, 2048, alongside, rows);
  else
    parallelFor(n, 4096, rows);
  int to_ltd = 0, degenerate = 0;
  for (const auto& c : per_worker) to_ltd += c.straightest_to_ltd, degenerate += c.degenerate_rings;
  counts.straightest_to_ltd += to_ltd;
  counts.degenerate_rings += degenerate;
  return weights;
}

}  // namespace sdp
