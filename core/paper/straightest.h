// The paper's §2.1: local straightest paths through an interior vertex V_i, and the LTD
// (Polthier-Schmies) straightest direction it is compared with and falls back to.
//
// Both answer the same question for a neighbour V_j of V_i: where does the path that comes
// from V_j and runs "straight" through V_i leave the 1-ring? The answer is a point X on a ring
// edge (V_a, V_b); V_i then lies on the segment V_j X, which gives the barycentric weights.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace sdp {

// A vertex's 1-ring, copied out for the local computations: neighbours counter-clockwise.
struct Ring {
  Eigen::Vector3d center;
  std::vector<Eigen::Vector3d> neighbour;  // n neighbours; face k = (center, k, k+1 mod n)
  std::vector<double> angle;               // angle at the centre in face k (3D)
  double total_angle = 0;
  int size() const { return static_cast<int>(neighbour.size()); }
};

// Fills angles; returns false when the ring is degenerate (zero-length edge, zero-area face at
// the centre, or non-finite values), where no geometric weight is trustworthy.
bool prepareRing(Ring& ring);

// Exit point X = (1 - s) * neighbour[a] + s * neighbour[b], b = a + 1 mod n, and d2 = |X - V_i|.
struct RingExit {
  int a = -1;
  double s = 0;
  double d2 = 0;
};

// Eq. (2): area-weighted average of the ring's face normals, normalized.
Eigen::Vector3d baseNormal(const Ring& ring);

// The paper's cutting plane P through V_i and V_j containing N_B; the exit is the crossing of
// P with a ring edge not incident to V_j on the far side of V_i (smallest cosine with the
// in-plane direction of V_j; ties keep the first edge counter-clockwise from j). Inside the
// crossed face the path runs along N_face x N_P (eq. 3), which is the segment V_i X. Returns
// false when P crosses no far-side edge (a non-star-shaped ring).
bool cuttingPlaneExit(const Ring& ring, const Eigen::Vector3d& base_normal, int j, RingExit& exit);

// Polthier-Schmies straightest direction: equal total angle (θ/2) on both sides of the path,
// measured with the 3D angles of the fan. Always defined on a prepared ring.
RingExit equalAngleExit(const Ring& ring, int j);

// Adds the barycentric weights of V_i on the segment V_j X to w (size n).
void addSegmentWeights(const Ring& ring, int j, const RingExit& exit, double* w);

}  // namespace sdp
