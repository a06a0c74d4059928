#include "stretch_newton.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <optional>

#include "checked_descent.h"
#include "free_boundary.h"
#include "geometry.h"

namespace sdp {
namespace {

// J = sum_k uv_k g_k^T over the corners k: the gradients g_k of the corners' hat functions in
// the flat 3D triangle.
struct FaceFrame {
  std::array<Eigen::Vector2d, 3> g;
  double area = 0;  // 3D area; 0 for a face without one (it then adds nothing)
};

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

// (a, b, c, d) = J row by row: u's gradient, then v's.
Eigen::Vector4d jacobian(const FaceFrame& frame, const std::array<int, 3>& t, const LocalUVs& uv) {
  Eigen::Vector4d J = Eigen::Vector4d::Zero();
  for (int k = 0; k < 3; ++k) {
    J.head<2>() += uv[t[k]].x() * frame.g[k];
    J.tail<2>() += uv[t[k]].y() * frame.g[k];
  }
  return J;
}

double determinant(const Eigen::Vector4d& J) {
  return J[0] * J[3] - J[1] * J[2];
}

// Q = sum A |J|^2 / det^2 and S = sum A det; Q * S is the scale-invariant energy (+inf when a
// face with area has collapsed or flipped).
struct Energy {
  double Q = 0, S = 0;
  double value() const { return Q * S; }
};

Energy energyOf(const Patch& patch, const std::vector<FaceFrame>& frames, const LocalUVs& uv) {
  Energy e;
  for (int f = 0; f < patch.real_face_count; ++f) {
    if (frames[f].area == 0) continue;
    const Eigen::Vector4d J = jacobian(frames[f], patch.face[f], uv);
    const double det = determinant(J);
    if (!(det > 0)) return {std::numeric_limits<double>::infinity(), 1.0};
    e.Q += frames[f].area * J.squaredNorm() / (det * det);
    e.S += frames[f].area * det;
  }
  return e;
}

// The largest t for which no face's signed UV area reaches zero along uv + t d.
double stepBeforeCollapse(const Patch& patch, const LocalUVs& uv, const LocalUVs& d) {
  double limit = std::numeric_limits<double>::infinity();
  for (int f = 0; f < patch.real_face_count; ++f) {
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
  return limit;
}

// The Newton system at `uv`: the gradient of Q * S and the Hessian of S * Q (the term that
// bends; S's own curvature and the cross terms dQ dS^T are left out, as the energy is
// scale-invariant and each step is rescaled: a positive definite approximation, so the step
// still descends), per face made positive semi-definite; u and v of vertex i at 2i and 2i + 1.
void assembleNewtonSystem(const Patch& patch, const std::vector<FaceFrame>& frames,
                          const LocalUVs& uv, const Energy& energy, Eigen::VectorXd& gradient,
                          std::vector<Eigen::Triplet<double>>& entries) {
  const int n = patch.real_vertex_count;
  const int faces = patch.real_face_count;
  gradient.setZero();
  entries.clear();
  entries.reserve(static_cast<size_t>(faces) * 36 + 2 * n);
  for (int f = 0; f < faces; ++f) {
    const FaceFrame& frame = frames[f];
    if (frame.area == 0) continue;
    const auto& t = patch.face[f];
    const Eigen::Vector4d J = jacobian(frame, t, uv);
    const double det = determinant(J), fro = J.squaredNorm();
    const Eigen::Vector4d cof(J[3], -J[2], -J[1], J[0]);  // d det / d J
    const double q2 = det * det, q3 = q2 * det, q4 = q2 * q2;
    const Eigen::Vector4d dJ =
        frame.area * (energy.S * (2 * J / q2 - 2 * fro / q3 * cof) + energy.Q * cof);
    Eigen::Matrix4d h = (2 / q2) * Eigen::Matrix4d::Identity() -
                        (4 / q3) * (J * cof.transpose() + cof * J.transpose()) +
                        (6 * fro / q4) * cof * cof.transpose();
    h(0, 3) -= 2 * fro / q3;
    h(3, 0) -= 2 * fro / q3;
    h(1, 2) += 2 * fro / q3;
    h(2, 1) += 2 * fro / q3;
    h *= energy.S * frame.area;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(h);
    const Eigen::Vector4d clamped = eigen.eigenvalues().cwiseMax(1e-8 * energy.S * frame.area / q2);
    h = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
    // d J / d (u0 u1 u2 v0 v1 v2)
    Eigen::Matrix<double, 4, 6> D = Eigen::Matrix<double, 4, 6>::Zero();
    for (int k = 0; k < 3; ++k) {
      D.block<2, 1>(0, k) = frame.g[k];
      D.block<2, 1>(2, 3 + k) = frame.g[k];
    }
    const Eigen::Matrix<double, 6, 1> g6 = D.transpose() * dJ;
    const Eigen::Matrix<double, 6, 6> k6 = D.transpose() * h * D;
    int index[6];
    for (int k = 0; k < 3; ++k) {
      index[k] = 2 * t[k];
      index[3 + k] = 2 * t[k] + 1;
    }
    for (int r = 0; r < 6; ++r) {
      gradient[index[r]] += g6[r];
      for (int c = 0; c < 6; ++c) entries.emplace_back(index[r], index[c], k6(r, c));
    }
  }
  // A small multiple of the identity fixes the translation the energy does not see.
  double trace = 0;
  for (const auto& e : entries)
    if (e.row() == e.col()) trace += e.value();
  const double shift = 1e-8 * trace / (2 * n);
  for (int i = 0; i < 2 * n; ++i) entries.emplace_back(i, i, shift);
}

}  // namespace

LocalUVs minimizeStretchWithFreeBoundary(const Patch& patch, const LocalUVs& uv, int steps,
                                         StretchMetrics& metrics, StretchNewtonCounts& counts,
                                         const Progress& progress, const RefineBudget& budget) {
  const int n = patch.real_vertex_count;
  const int faces = patch.real_face_count;
  if (steps <= 0 || n < 3 || faces == 0) return uv;
  if (n > kStretchNewtonMaxVertices) {
    counts.skipped = true;
    return uv;
  }
  if (budget.expired()) return uv;
  std::optional<CheckedDescent> descent;  // made inside the try: its allocations may fail too
  try {
    const double total_area = patchArea3d(patch);
    if (!(total_area > 0)) return uv;
    std::vector<FaceFrame> frames(faces);
    for (int f = 0; f < faces; ++f) frames[f] = faceFrame(patch, f, 1e-14 * total_area);

    // Start at the 3D size, as the ARAP steps do (the energy does not see the scale; the
    // Hessian's conditioning does).
    // Scaling by s multiplies S by s^2 and Q by 1 / s^2, so the energy of the rescaled map
    // follows from `e`, the map's energy before.
    auto rescale = [&](LocalUVs& map, Energy& e) {
      if (!(e.S > 0) || !std::isfinite(e.Q)) return false;
      const double s = std::sqrt(total_area / e.S);
      for (int v = 0; v < n; ++v) map[v] *= s;
      e.Q /= s * s;
      e.S = total_area;
      return true;
    };
    descent.emplace(patch, uv, metrics, budget, progress, Stage::Newton);
    LocalUVs& current = descent->current();  // the best map stays `uv` until a step beats it
    Energy energy = energyOf(patch, frames, current);
    if (!rescale(current, energy)) return uv;

    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor;
    bool analyzed = false;
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::SparseMatrix<double> H(2 * n, 2 * n);
    Eigen::VectorXd gradient(2 * n), direction(2 * n);
    LocalUVs step(current.size(), Eigen::Vector2d::Zero());

    for (int it = 0; it < steps; ++it) {
      if (!descent->beginStep(it, steps)) break;
      assembleNewtonSystem(patch, frames, current, energy, gradient, entries);
      H.setFromTriplets(entries.begin(), entries.end());
      if (!analyzed) {
        factor.analyzePattern(H);
        analyzed = true;
      }
      factor.factorize(H);
      if (factor.info() != Eigen::Success) {
        counts.stopped = true;
        break;
      }
      direction = factor.solve(-gradient);
      if (factor.info() != Eigen::Success || !direction.allFinite()) {
        counts.stopped = true;
        break;
      }
      double slope = gradient.dot(direction);
      if (!(slope < 0)) {  // not a descent direction (numerically): plain gradient descent
        direction = -gradient;
        slope = -gradient.squaredNorm();
        if (!(slope < 0)) {
          counts.stopped = true;
          break;
        }
      }
      for (int v = 0; v < n; ++v) step[v] = direction.segment<2>(2 * v);
      descent->recordStepTime();  // the factorization is most of a step's time

      // Capped short of the first collapse, then halved until the energy drops enough; the
      // map is checked at the scale it is returned at.
      Energy trial;
      const auto sufficientDecrease = [&](LocalUVs& candidate, double length) {
        trial = energyOf(patch, frames, candidate);
        if (!(trial.value() <= energy.value() + 1e-4 * length * slope)) return false;
        return rescale(candidate, trial);
      };
      const double length = std::min(1.0, 0.8 * stepBeforeCollapse(patch, current, step));
      const CheckedDescent::Outcome outcome =
          descent->tryStep(step, length, 30, sufficientDecrease);
      if (!outcome.taken) {
        counts.stopped = true;
        break;
      }
      ++counts.steps_taken;
      const double before = energy.value();
      energy = trial;
      if (!outcome.gained) break;
      if (!(energy.value() < before * (1 - 1e-9))) {
        counts.stopped = true;  // converged as far as doubles tell
        break;
      }
    }
    return descent->takeBest();
  } catch (const std::bad_alloc&) {
    counts.skipped = true;  // the factor did not fit: keep the best map so far
    return descent ? descent->takeBest() : uv;
  }
}

}  // namespace sdp
