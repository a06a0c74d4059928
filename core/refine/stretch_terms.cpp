#include "stretch_terms.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/common/geometry.h"
#include "core/common/parallel.h"
#include "free_boundary.h"

namespace sdp {

StretchModes stretchModes(const Eigen::Vector4d& J, double area_weight) {
  const double det = J[0] * J[3] - J[1] * J[2], fro = J.squaredNorm();
  // Singular values: (s1 + s2)^2 = |J|^2 + 2 det and (s1 - s2)^2 = |J|^2 - 2 det. Every
  // eigenvalue below is a product of powers of 1/s1 and 1/s2, so two divisions give them all
  // (the function is bound by the latency of its divisions and square roots).
  const double sum = std::sqrt(std::max(fro + 2 * det, 0.0));
  const double s1 = 0.5 * (sum + std::sqrt(std::max(fro - 2 * det, 0.0)));
  const double inv_det = 1 / det, inv1 = 1 / s1;
  const double s2 = det * inv1, inv2 = s1 * inv_det;
  // V's first column: the eigenvector of J^T J for s1^2, from whichever of the two candidate
  // rows is longer (both vanish when s1 = s2, where any basis serves).
  const double p = J[0] * J[0] + J[2] * J[2], q = J[1] * J[1] + J[3] * J[3];
  const double r = J[0] * J[1] + J[2] * J[3], l1 = s1 * s1;
  const Eigen::Vector2d x(l1 - q, r), y(r, l1 - p);
  Eigen::Vector2d v1 = x.squaredNorm() >= y.squaredNorm() ? x : y;
  const double v1_norm2 = v1.squaredNorm();
  v1 = v1_norm2 > 0 ? Eigen::Vector2d(v1 / std::sqrt(v1_norm2)) : Eigen::Vector2d(1, 0);
  // J v1 = s1 u1 (s1 > 0 as det > 0).
  const Eigen::Vector2d u1 =
      inv1 * Eigen::Vector2d(J[0] * v1.x() + J[1] * v1.y(), J[2] * v1.x() + J[3] * v1.y());
  const Eigen::Vector2d v2(-v1.y(), v1.x()), u2(-u1.y(), u1.x());
  // u v^T in J's order (row by row).
  const auto outer = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    return Eigen::Vector4d(u.x() * v.x(), u.x() * v.y(), u.y() * v.x(), u.y() * v.y());
  };
  const Eigen::Vector4d twist = std::sqrt(0.5) * (outer(u2, v1) - outer(u1, v2));
  const Eigen::Vector4d flip = std::sqrt(0.5) * (outer(u2, v1) + outer(u1, v2));
  const double floor = 1e-8 * inv_det * inv_det;
  const double inv1_2 = inv1 * inv1, inv2_2 = inv2 * inv2;
  const double inv_both_3 = inv1_2 * inv1 * inv2_2 * inv2;  // 1 / (s1 s2)^3
  // -2 (1/s1^3 + 1/s2^3) / (s1 + s2) = -2 (s1^2 - s1 s2 + s2^2) / (s1 s2)^3, and det's Hessian
  // raises the twist by area_weight and lowers the flip by it.
  const double s1s2 = s1 * s2, squares = s1 * s1 + s2 * s2;
  StretchModes modes;
  modes.value[0] = std::max(-2 * (squares - s1s2) * inv_both_3 + area_weight, floor);
  modes.vector[0] = twist;
  modes.value[1] = std::max(2 * (squares + s1s2) * inv_both_3 - area_weight, floor);
  modes.vector[1] = flip;
  // The scalings: [[6/s1^4, area_weight], [area_weight, 6/s2^4]] over (u1 v1^T, u2 v2^T), its
  // eigenvalues raised to the floor.
  const double a = 6 * inv1_2 * inv1_2, b = 6 * inv2_2 * inv2_2;
  const double mid = 0.5 * (a + b), half_gap = 0.5 * (a - b);
  double rad = std::sqrt(half_gap * half_gap + area_weight * area_weight);
  if (!std::isfinite(rad)) rad = std::hypot(half_gap, area_weight);  // s2 below ~1e-38
  const double e1 = std::max(mid + rad, floor), e2 = std::max(mid - rad, floor);
  // The larger eigenvalue's eigenvector: (area_weight, mid + rad - a), or the axis of the
  // larger of a and b when area_weight = 0.
  Eigen::Vector2d top(area_weight, mid + rad - a);
  const double top_norm2 = top.squaredNorm();
  if (!(top_norm2 > 0))
    top = a >= b ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1);
  else
    top /= std::sqrt(top_norm2);
  const Eigen::Vector4d x1 = outer(u1, v1), x2 = outer(u2, v2);
  modes.value[2] = e1;
  modes.vector[2] = top.x() * x1 + top.y() * x2;
  modes.value[3] = e2;
  modes.vector[3] = -top.y() * x1 + top.x() * x2;
  return modes;
}

Eigen::Matrix4d StretchModes::matrix() const {
  Eigen::Matrix4d h = Eigen::Matrix4d::Zero();
  for (int m = 0; m < 4; ++m) h.noalias() += value[m] * vector[m] * vector[m].transpose();
  return h;
}

Eigen::Matrix4d stretchHessian(const Eigen::Vector4d& J, double area_weight) {
  return stretchModes(J, area_weight).matrix();
}

FaceFrame faceFrame(const Patch& patch, int f, double tiny_area) {
  const std::array<Eigen::Vector2d, 3> x = flatTriangle(patch, f);
  FaceFrame frame;
  const double twice_area = x[1].x() * x[2].y();
  if (!(0.5 * twice_area > tiny_area)) {
    for (auto& g : frame.g) g.setZero();
    return frame;
  }
  Eigen::Matrix2d edges;  // columns: the two edges from corner 0, laid flat
  edges << x[1], x[2];
  const Eigen::Matrix2d inverse = edges.inverse();
  frame.g[1] = inverse.row(0).transpose();
  frame.g[2] = inverse.row(1).transpose();
  frame.g[0] = -frame.g[1] - frame.g[2];
  frame.area = 0.5 * twice_area;
  return frame;
}

// Both passes run on fixed ranges of faces (parallel.h): the sums are added in range order, the
// same bits on any number of cores.
Energy energyOf(const Patch& patch, const std::vector<FaceFrame>& frames, const LocalUVs& uv) {
  const int faces = patch.real_face_count;
  std::vector<Energy> partial(faceSumSlots(faces));
  std::vector<char> collapsed(partial.size(), 0);
  parallelForSlots(faces, static_cast<int>(partial.size()), [&](int begin, int end, int slot) {
    Energy e;
    for (int f = begin; f < end; ++f) {
      if (frames[f].area == 0) continue;
      const Eigen::Vector4d J = jacobian(frames[f], patch.face[f], uv);
      const double det = determinant(J);
      if (!(det > 0)) {
        collapsed[slot] = 1;
        return;
      }
      e.Q += frames[f].area * J.squaredNorm() / (det * det);
      e.S += frames[f].area * det;
    }
    partial[slot] = e;
  });
  Energy e;
  for (size_t slot = 0; slot < partial.size(); ++slot) {
    if (collapsed[slot]) return {std::numeric_limits<double>::infinity(), 1.0};
    e.Q += partial[slot].Q;
    e.S += partial[slot].S;
  }
  return e;
}

// The largest t for which no face's signed UV area reaches zero along uv + t d.
double stepBeforeCollapse(const Patch& patch, const LocalUVs& uv, const LocalUVs& d) {
  const int faces = patch.real_face_count;
  std::vector<double> partial(faceSumSlots(faces), std::numeric_limits<double>::infinity());
  parallelForSlots(faces, static_cast<int>(partial.size()), [&](int begin, int end, int slot) {
    double limit = std::numeric_limits<double>::infinity();
    for (int f = begin; f < end; ++f) {
      const auto& t = patch.face[f];
      const Eigen::Vector2d p0 = uv[t[1]] - uv[t[0]], p1 = uv[t[2]] - uv[t[0]];
      const Eigen::Vector2d d0 = d[t[1]] - d[t[0]], d1 = d[t[2]] - d[t[0]];
      // area(t) ~ qc + qb t + qa t^2
      const double qa = cross2(d0, d1), qb = cross2(p0, d1) + cross2(d0, p1), qc = cross2(p0, p1);
      auto consider = [&](double root) {
        if (root > 0 && std::isfinite(root)) limit = std::min(limit, root);
      };
      if (qa == 0) {
        if (qb != 0) consider(-qc / qb);
        continue;
      }
      const double disc = qb * qb - 4 * qa * qc;
      if (disc < 0) continue;
      // Roots without cancellation: q = -(qb + sign(qb) sqrt(disc)) / 2, roots q / qa and qc / q.
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      consider(q / qa);
      if (q != 0) consider(qc / q);
    }
    partial[slot] = limit;
  });
  return *std::min_element(partial.begin(), partial.end());
}

// One face's share of the Newton system at its Jacobian J, in J's coordinates: the gradient
// dJ of Q * S and, made positive semi-definite (stretchHessian), the Hessian of the face's
// S * A |J|^2 / det^2 + Q * A det: summed over the faces, S Hess(Q) + Q Hess(S). Only the cross
// terms dQ dS^T are left out (the energy is scale-invariant and each step is rescaled).
void faceNewtonTerms(const FaceFrame& frame, const Eigen::Vector4d& J, const Energy& energy,
                     Eigen::Vector4d& dJ, StretchModes& h) {
  const double det = determinant(J), fro = J.squaredNorm();
  const Eigen::Vector4d cof(J[3], -J[2], -J[1], J[0]);  // d det / d J
  const double q2 = det * det, q3 = q2 * det;
  dJ = frame.area * (energy.S * (2 * J / q2 - 2 * fro / q3 * cof) + energy.Q * cof);
  h = stretchModes(J, energy.Q / energy.S);
  for (double& value : h.value) value *= energy.S * frame.area;
}

void faceNewtonTerms(const FaceFrame& frame, const Eigen::Vector4d& J, const Energy& energy,
                     Eigen::Vector4d& dJ, Eigen::Matrix4d& h) {
  StretchModes modes;
  faceNewtonTerms(frame, J, energy, dJ, modes);
  h = modes.matrix();
}

}  // namespace sdp
