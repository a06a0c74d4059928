// The L2 stretch of a map face by face, as the Newton steps (stretch_newton.h) and their coarse
// grid (grid_newton.h) use it: L2^2 = Q * S / (2 A^2) with Q = sum_f A_f |J_f^-1|^2 (J_f the map
// from the flat 3D triangle to its UV triangle, A_f its 3D area, A their sum) and S = sum_f A_f
// det J_f (the UV area).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/common/patch.h"
#include "core/paper/solve.h"

namespace sdp {

// J = sum_k uv_k g_k^T over the corners k: the gradients g_k of the corners' hat functions in
// the flat 3D triangle.
struct FaceFrame {
  std::array<Eigen::Vector2d, 3> g;
  double area = 0;  // 3D area; 0 for a face without one (it then adds nothing)
};

// The frame of face f; a face of 3D area below tiny_area gets none (area 0, zero gradients).
FaceFrame faceFrame(const Patch& patch, int f, double tiny_area);

inline  // (a, b, c, d) = J row by row: u's gradient, then v's.
    Eigen::Vector4d
    jacobian(const FaceFrame& frame, const std::array<int, 3>& t, const LocalUVs& uv) {
  Eigen::Vector4d J = Eigen::Vector4d::Zero();
  for (int k = 0; k < 3; ++k) {
    J.head<2>() += uv[t[k]].x() * frame.g[k];
    J.tail<2>() += uv[t[k]].y() * frame.g[k];
  }
  return J;
}

inline double determinant(const Eigen::Vector4d& J) {
  return J[0] * J[3] - J[1] * J[2];
}

// Q = sum A |J|^2 / det^2 and S = sum A det; Q * S is the scale-invariant energy (+inf when a
// face with area has collapsed or flipped).
struct Energy {
  double Q = 0, S = 0;
  double value() const { return Q * S; }
};

Energy energyOf(const Patch& patch, const std::vector<FaceFrame>& frames, const LocalUVs& uv);

// The largest t for which no face's signed UV area reaches zero along uv + t d.
double stepBeforeCollapse(const Patch& patch, const LocalUVs& uv, const LocalUVs& d);

// The Hessian of |J|^2 / det(J)^2 + area_weight * det(J) = 1/s1^2 + 1/s2^2 + w s1 s2 (s1, s2
// J's singular values; det > 0) over J = (a, b, c, d) row by row, made positive semi-definite.
// The energy is isotropic, so its Hessian's eigenvectors are known in J = U diag(s1, s2) V^T
// (Smith, de Goes and Kim, "Analytic eigensystems for isotropic distortion energies", 2019):
// the twist U [0 -1; 1 0] V^T / sqrt 2 with -2 (1/s1^3 + 1/s2^3) / (s1 + s2) + w, the flip
// U [0 1; 1 0] V^T / sqrt 2 with 2 (s1^2 + s1 s2 + s2^2) / (s1 s2)^3 - w, and the scalings
// U e_i e_j^T V^T (i = j) coupled by [[6 / s1^4, w], [w, 6 / s2^4]]. Eigenvalues below
// 1e-8 / det^2 are raised to it: the same projection as a 4x4 eigensolver's, which took half
// of a matrix-free Newton step's time.
Eigen::Matrix4d stretchHessian(const Eigen::Vector4d& J, double area_weight = 0);
// The same Hessian as its four eigen-pairs (unit vectors in J's coordinates, values raised to
// the floor): a sum over faces of its products with a few vectors costs less from the pairs
// than from the 4x4 matrix.
struct StretchModes {
  std::array<double, 4> value;
  std::array<Eigen::Vector4d, 4> vector;
  Eigen::Matrix4d matrix() const;  // sum_m value[m] vector[m] vector[m]^T
};
StretchModes stretchModes(const Eigen::Vector4d& J, double area_weight = 0);

// One face's share of the Newton system at its Jacobian J, in J's coordinates: the gradient
// dJ of Q * S and, made positive semi-definite (stretchHessian), the Hessian of the face's
// S * A |J|^2 / det^2 + Q * A det. Summed over the faces that is S Hess(Q) + Q Hess(S): the
// UV area's curvature, which lives on the free boundary, is kept (leaving it out cost the
// default map 0.8-1.6 % of L2 on the face scans; docs/measurements.md). Only the cross terms
// dQ dS^T are left out (the energy is scale-invariant and each step is rescaled).
void faceNewtonTerms(const FaceFrame& frame, const Eigen::Vector4d& J, const Energy& energy,
                     Eigen::Vector4d& dJ, Eigen::Matrix4d& h);
// The same with the Hessian as its eigen-pairs.
void faceNewtonTerms(const FaceFrame& frame, const Eigen::Vector4d& J, const Energy& energy,
                     Eigen::Vector4d& dJ, StretchModes& h);

}  // namespace sdp
