#include "weights.h"

#include "geometry.h"
#include "parallel.h"

#include <cmath>

namespace sdp {
namespace {

constexpr double kPi = 3.14159265358979323846;

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

bool ringWeights(const Ring& ring, WeightScheme scheme, double* w, int& straightest_to_ltd) {
  const int n = ring.size();
  for (int k = 0; k < n; ++k) w[k] = 0;
  if (scheme == WeightScheme::Uniform) {
    uniformWeights(n, w);
    return true;
  }
  switch (scheme) {
    case WeightScheme::Straightest: {
      const Eigen::Vector3d normal = baseNormal(ring);
      for (int j = 0; j < n; ++j) {
        RingExit exit;
        if (!cuttingPlaneExit(ring, normal, j, exit)) {
          exit = equalAngleExit(ring, j);
          ++straightest_to_ltd;
        }
        addSegmentWeights(ring, j, exit, w);
      }
      break;
    }
    case WeightScheme::Ltd:
      for (int j = 0; j < n; ++j) addSegmentWeights(ring, j, equalAngleExit(ring, j), w);
      break;
    case WeightScheme::Floater:
      if (!floaterWeights(ring, w)) return false;
      break;
    case WeightScheme::MeanValue:
      meanValueWeights(ring, w);
      break;
    case WeightScheme::Uniform:
      break;
  }
  return normalizeRow(n, w);
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
  auto rows = [&](int begin, int end, int worker) {
    Ring ring;
    WeightCounts& local = per_worker[worker];
    for (int v = begin; v < end; ++v) {
      if (patch.on_boundary[v]) continue;
      gatherRing(patch, v, ring);
      double* w = &weights[patch.ring_begin[v]];
      int vertex_to_ltd = 0;
      const bool ok = (scheme == WeightScheme::Uniform || prepareRing(ring)) &&
                      ringWeights(ring, scheme, w, vertex_to_ltd);
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
