#include "straightest.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/common/geometry.h"

namespace sdp {

bool prepareRing(Ring& ring) {
  const int n = ring.size();
  if (n < 3) return false;
  double longest = 0;
  for (const auto& q : ring.neighbour) longest = std::max(longest, (q - ring.center).norm());
  if (!(longest > 0) || !std::isfinite(longest)) return false;
  ring.angle.resize(n);
  ring.total_angle = 0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d e0 = ring.neighbour[k] - ring.center;
    const Eigen::Vector3d e1 = ring.neighbour[(k + 1) % n] - ring.center;
    const double l0 = e0.norm(), l1 = e1.norm();
    if (l0 < 1e-12 * longest || l1 < 1e-12 * longest) return false;
    const double sine = e0.cross(e1).norm() / (l0 * l1);
    if (!(sine > 1e-10)) return false;  // zero-area face at the centre
    ring.angle[k] = std::atan2(e0.cross(e1).norm(), e0.dot(e1));
    ring.total_angle += ring.angle[k];
  }
  return std::isfinite(ring.total_angle);
}

Eigen::Vector3d baseNormal(const Ring& ring) {
  const int n = ring.size();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  // |e0 x e1| is twice the face area, so the plain sum of cross products is the area-weighted
  // sum of unit normals.
  for (int k = 0; k < n; ++k)
    sum += (ring.neighbour[k] - ring.center).cross(ring.neighbour[(k + 1) % n] - ring.center);
  const double len = sum.norm();
  return len > 0 ? Eigen::Vector3d(sum / len) : Eigen::Vector3d::Zero();
}

bool cuttingPlaneExit(const Ring& ring, const Eigen::Vector3d& base_normal, int j, RingExit& exit) {
  const int n = ring.size();
  const Eigen::Vector3d to_j = ring.neighbour[j] - ring.center;
  // In-plane direction of V_j: its projection onto the base plane (it lies in P too).
  Eigen::Vector3d t = to_j - to_j.dot(base_normal) * base_normal;
  const double t_len = t.norm();
  if (!(t_len > 1e-12 * to_j.norm())) return false;
  t /= t_len;
  const Eigen::Vector3d plane_normal = t.cross(base_normal).normalized();
  double best_cosine = 0;  // must be strictly on the far side
  bool found = false;
  for (int step = 1; step < n - 1; ++step) {  // edges (a, a+1) not incident to j
    const int a = (j + step) % n, b = (a + 1) % n;
    const Eigen::Vector3d pa = ring.neighbour[a] - ring.center;
    const Eigen::Vector3d pb = ring.neighbour[b] - ring.center;
    const double da = plane_normal.dot(pa), db = plane_normal.dot(pb);
    if ((da > 0 && db > 0) || (da < 0 && db < 0) || da == db) continue;
    const double s = da / (da - db);
    const Eigen::Vector3d x = pa + s * (pb - pa);
    const double d2 = x.norm();
    if (!(d2 > 0)) continue;
    const double cosine = x.dot(t) / d2;
    if (cosine < best_cosine) {
      best_cosine = cosine;
      exit = {a, s, d2};
      found = true;
    }
  }
  return found;
}

RingExit equalAngleExit(const Ring& ring, int j) {
  const int n = ring.size();
  const double half = 0.5 * ring.total_angle;
  double accumulated = 0;
  int a = j;
  for (int step = 0; step < n; ++step, a = (a + 1) % n) {
    if (accumulated + ring.angle[a] >= half || step == n - 1) break;
    accumulated += ring.angle[a];
  }
  const int b = (a + 1) % n;
  // Lay face (centre, a, b) flat with the centre at the origin and V_a on the x axis; the path
  // leaves the centre at angle alpha from V_a.
  const double alpha = std::clamp(half - accumulated, 0.0, ring.angle[a]);
  const double la = (ring.neighbour[a] - ring.center).norm();
  const double lb = (ring.neighbour[b] - ring.center).norm();
  const Eigen::Vector2d A(la, 0), B(lb * std::cos(ring.angle[a]), lb * std::sin(ring.angle[a]));
  const Eigen::Vector2d dir(std::cos(alpha), std::sin(alpha));
  // Solve A + s (B - A) = r dir for s: cross both sides with dir.
  const Eigen::Vector2d ab = B - A;
  const double denom = cross2(ab, dir);
  double s = denom != 0 ? -cross2(A, dir) / denom : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  return {a, s, (A + s * ab).norm()};
}

void addSegmentWeights(const Ring& ring, int j, const RingExit& exit, double* w) {
  const int n = ring.size();
  const double d1 = (ring.neighbour[j] - ring.center).norm();
  const double d2 = exit.d2;
  const double sum = d1 + d2;
  w[j] += d2 / sum;
  w[exit.a] += d1 / sum * (1 - exit.s);
  w[(exit.a + 1) % n] += d1 / sum * exit.s;
}

}  // namespace sdp
