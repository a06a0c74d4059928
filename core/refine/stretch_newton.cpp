#include "stretch_newton.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <optional>
#include <utility>

#include "checked_descent.h"
#include "core/common/geometry.h"
#include "core/common/parallel.h"
#include "core/common/work.h"
#include "core/linear/block_multigrid.h"
#include "core/linear/krylov.h"
#include "core/linear/solve_path.h"
#include "free_boundary.h"
#include "grid_newton.h"
#include "stretch_terms.h"

namespace sdp {

namespace {

// The Newton system at `uv` assembled for the sparse factor; u and v of vertex i at 2i and
// 2i + 1.
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
    Eigen::Vector4d dJ;
    Eigen::Matrix4d h;
    faceNewtonTerms(frame, jacobian(frame, t, uv), energy, dJ, h);
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

// The Newton system of a large patch, never factored (its sparse factor would not fit: 59% of a
// step's time already at 11k vertices): assembled as 2x2 blocks per vertex pair (u and v
// together) on the pattern of a scalar stand-in, and solved by truncated conjugate gradients
// preconditioned by one cycle of a coupled multigrid (linear/block_multigrid.h). The stand-in is
// the Laplacian the same faces give with the 2x2 metric (h_uu + h_vv) / 2 in place of h (g_i^T M
// g_j between corners i and j), its positive off-diagonal entries (obtuse corners) moved onto
// the diagonal so it is the M-matrix the aggregation needs; it decides the aggregates and
// prolongations, while the coarse levels are products of the true blocks, so the u-v coupling
// is kept. With the stand-in's own cycle (the coupling dropped) 20 iterations halved the
// residual; with this one 5 iterations give longer steps: face s2 (414k vertices), 10 steps
// without a work limit, L2 1.2809 -> 1.2740 in 21.4 -> 13.2 s (bench/results/defaults.md).
class AssembledNewtonSystem {
 public:
  AssembledNewtonSystem(const Patch& patch, const std::vector<FaceFrame>& frames)
      : patch_(patch), frames_(frames), hessian_(frames.size()), slot_(frames.size()) {
    const int n = patch.real_vertex_count;
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(9 * frames.size());
    for (int f = 0; f < patch.real_face_count; ++f)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) pattern.emplace_back(patch.face[f][a], patch.face[f][b], 0.0);
    proxy_.resize(n, n);
    proxy_.setFromTriplets(pattern.begin(), pattern.end());
    spent_work_ += 9.0 * patch.real_face_count * 10 * WorkCosts::kNonzero;  // triplets, sorted
    std::vector<Eigen::Triplet<double>>().swap(pattern);
    proxy_.makeCompressed();
    // Where each face's 3 x 3 block lands among the proxy's values, found once.
    const int* outer = proxy_.outerIndexPtr();
    const int* inner = proxy_.innerIndexPtr();
    for (int f = 0; f < patch.real_face_count; ++f)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const int row = patch.face[f][a], col = patch.face[f][b];
          slot_[f][3 * a + b] = static_cast<int>(
              std::lower_bound(inner + outer[col], inner + outer[col + 1], row) - inner);
        }
  }

  // The gradient and the face Hessians at `uv`, H's 2x2 blocks and the stand-in's values from
  // them, and the preconditioner. Returns whether it could be built.
  bool update(const LocalUVs& uv, const Energy& energy, Eigen::VectorXd& gradient) {
    const int n = patch_.real_vertex_count;
    sumOverFaces(gradient, [&](int f, Eigen::VectorXd& out) {
      Eigen::Vector4d dJ;
      Eigen::Matrix4d h;
      faceNewtonTerms(frames_[f], jacobian(frames_[f], patch_.face[f], uv), energy, dJ, h);
      hessian_[f] = pack(h);
      scatter(frames_[f], patch_.face[f], dJ, out);
    });

    double* value = proxy_.valuePtr();
    std::fill(value, value + proxy_.nonZeros(), 0.0);
    blocks_.assign(4 * static_cast<size_t>(proxy_.nonZeros()), 0.0);
    double proxy_trace = 0;  // half the trace of H: M is the mean of the u-u and v-v blocks
    for (int f = 0; f < patch_.real_face_count; ++f) {
      if (frames_[f].area == 0) continue;
      const Eigen::Matrix4d h = unpack(hessian_[f]);
      const Eigen::Matrix2d M = 0.5 * (h.topLeftCorner<2, 2>() + h.bottomRightCorner<2, 2>());
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const Eigen::Vector2d& ga = frames_[f].g[a];
          const Eigen::Vector2d& gb = frames_[f].g[b];
          const int slot = slot_[f][3 * a + b];
          const double entry = ga.dot(M * gb);
          value[slot] += entry;
          if (a == b) proxy_trace += entry;
          // The 2x2 block of H at (a, b): u and v of corner a against u and v of corner b.
          double* block = &blocks_[4 * static_cast<size_t>(slot)];
          block[0] += ga.dot(h.topLeftCorner<2, 2>() * gb);
          block[1] += ga.dot(h.topRightCorner<2, 2>() * gb);
          block[2] += ga.dot(h.bottomLeftCorner<2, 2>() * gb);
          block[3] += ga.dot(h.bottomRightCorner<2, 2>() * gb);
        }
    }
    shift_ = 1e-8 * (2 * proxy_trace) / (2 * n);  // as in assembleNewtonSystem
    // A positive entry p at (i, j) is moved onto the diagonal at i and j: the proxy grows by
    // p (e_i - e_j)(e_i - e_j)^T, so it stays positive semi-definite and becomes a weighted
    // graph Laplacian (rows summing to zero) plus the shift.
    for (int col = 0; col < n; ++col) {
      double moved = 0;
      double* diagonal = nullptr;
      for (Eigen::SparseMatrix<double>::InnerIterator it(proxy_, col); it; ++it) {
        if (it.row() == col) {
          diagonal = &it.valueRef();
        } else if (it.value() > 0) {
          moved += it.value();
          it.valueRef() = 0;
        }
      }
      if (diagonal) *diagonal += moved + shift_;
      // The shift on H's own diagonal blocks too: the preconditioner and the products see the
      // same matrix.
      for (int k = proxy_.outerIndexPtr()[col]; k < proxy_.outerIndexPtr()[col + 1]; ++k)
        if (proxy_.innerIndexPtr()[k] == col) {
          blocks_[4 * static_cast<size_t>(k)] += shift_;
          blocks_[4 * static_cast<size_t>(k) + 3] += shift_;
        }
    }
    spent_work_ +=
        patch_.real_face_count * (WorkCosts::kNewtonHessianFace + 45 * WorkCosts::kNonzero) +
        4.0 * proxy_.nonZeros() * WorkCosts::kNonzero;
    const double before = preconditioner_.spentWork();
    const bool usable = preconditioner_.update(proxy_, blocks_);
    spent_work_ += preconditioner_.spentWork() - before;
    return usable;
  }

  // y = H x (H as assembleNewtonSystem would assemble it, from its 2x2 blocks): rows are
  // independent, so the cores share them with no sum to order.
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    y.resize(x.size());
    const int* outer = proxy_.outerIndexPtr();
    const int* inner = proxy_.innerIndexPtr();
    parallelFor(patch_.real_vertex_count, 8192, [&](int begin, int end, int) {
      for (int i = begin; i < end; ++i) {
        double u = 0, v = 0;
        // Column i of the symmetric pattern holds block (j, i); row i needs its transpose.
        for (int k = outer[i]; k < outer[i + 1]; ++k) {
          const double* b = &blocks_[4 * static_cast<size_t>(k)];
          const int j = inner[k];
          u += b[0] * x[2 * j] + b[2] * x[2 * j + 1];
          v += b[1] * x[2 * j] + b[3] * x[2 * j + 1];
        }
        y[2 * i] = u;
        y[2 * i + 1] = v;
      }
    });
  }

  // The Newton direction: truncated preconditioned CG (core/linear/krylov.h) for
  // H d = -gradient from d = 0, to the relative residual `tolerance`. Returns the iterations.
  int solve(const Eigen::VectorXd& gradient, Eigen::VectorXd& direction, double tolerance,
            int max_iterations) const {
    const Eigen::Index size = gradient.size();
    const int it = truncatedConjugateGradients(
        [&](const Eigen::VectorXd& p, Eigen::VectorXd& q) { multiply(p, q); },
        [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
          preconditioner_.applyCycle(r.data(), z.data());
        },
        -gradient, direction, tolerance, max_iterations);
    // Per iteration one product H p (face by face), one cycle (counted by the
    // preconditioner) and about eight vector passes.
    spent_work_ +=
        it * (4.0 * proxy_.nonZeros() * WorkCosts::kNonzero + 8.0 * size * WorkCosts::kVectorEntry);
    return it;
  }

  // Work (work.h) of the set-up, updates and solves so far.
  double spentWork() const { return spent_work_ + preconditioner_.spentWork(); }

 private:
  // out += D^T y for one face (y in J's coordinates: u's gradient, then v's).
  static void scatter(const FaceFrame& frame, const std::array<int, 3>& t, const Eigen::Vector4d& y,
                      Eigen::VectorXd& out) {
    for (int k = 0; k < 3; ++k) {
      out[2 * t[k]] += frame.g[k].dot(y.head<2>());
      out[2 * t[k] + 1] += frame.g[k].dot(y.tail<2>());
    }
  }

  // total = the sum over the faces with area of face(f, out), each face adding into `out`;
  // the faces are split into kFaceSumSlots fixed ranges (the cores share them out), each adding
  // into a vector of its own, and the vectors are summed in slot order: the same bits whatever
  // the number of cores.
  template <class Face>
  void sumOverFaces(Eigen::VectorXd& total, Face&& face) const {
    const int size = 2 * patch_.real_vertex_count;
    const int slots = std::clamp(patch_.real_face_count / 4096, 1, kFaceSumSlots);
    partial_.resize(slots);
    for (Eigen::VectorXd& p : partial_) p.setZero(size);
    parallelForSlots(patch_.real_face_count, slots, [&](int begin, int end, int slot) {
      for (int f = begin; f < end; ++f)
        if (frames_[f].area != 0) face(f, partial_[slot]);
    });
    total = partial_[0];
    for (size_t w = 1; w < partial_.size(); ++w) total += partial_[w];
  }
  // Four vectors of 2 x vertices doubles: all of a 4-core machine, at 106 MB for 1.65M vertices.
  static constexpr int kFaceSumSlots = 4;

  const Patch& patch_;
  const std::vector<FaceFrame>& frames_;
  // The symmetric 4x4 face Hessians, their 10 upper entries row by row (80 instead of 128 bytes
  // per face: 160 MB less at 1.65M vertices), per face with area (the others are never read).
  using PackedHessian = std::array<double, 10>;
  static PackedHessian pack(const Eigen::Matrix4d& h) {
    PackedHessian p;
    for (int r = 0, k = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c) p[k++] = h(r, c);
    return p;
  }
  static Eigen::Matrix4d unpack(const PackedHessian& p) {
    Eigen::Matrix4d h;
    for (int r = 0, k = 0; r < 4; ++r)
      for (int c = r; c < 4; ++c, ++k) h(r, c) = h(c, r) = p[k];
    return h;
  }
  std::vector<PackedHessian> hessian_;
  std::vector<std::array<int, 9>> slot_;
  Eigen::SparseMatrix<double> proxy_;
  std::vector<double> blocks_;  // H's 2x2 blocks, 4 per nonzero of proxy_ in its order
  CoupledMultigrid preconditioner_;
  double shift_ = 0;
  mutable std::vector<Eigen::VectorXd> partial_;
  mutable double spent_work_ = 0;
};

// Start at the 3D size, as the ARAP steps do (the energy does not see the scale; the Hessian's
// conditioning does). Scaling by s multiplies S by s^2 and Q by 1 / s^2, so the energy of the
// rescaled map follows from `e`, the map's energy before.
bool rescaleToArea(LocalUVs& map, int n, double total_area, Energy& e) {
  if (!(e.S > 0) || !std::isfinite(e.Q)) return false;
  const double s = std::sqrt(total_area / e.S);
  for (int v = 0; v < n; ++v) map[v] *= s;
  e.Q /= s * s;
  e.S = total_area;
  return true;
}

// The Newton direction at a map: on a large patch first in the grid's coarse space
// (GridNewtonSystem), then by the sparse factor or by conjugate gradients on the assembled blocks
// (linear/solve_path.h decides which), its work charged to the descent.
class NewtonDirection {
 public:
  NewtonDirection(const Patch& patch, const std::vector<FaceFrame>& frames,
                  const StretchNewtonSettings& settings)
      : patch_(patch),
        frames_(frames),
        settings_(settings),
        n_(patch.real_vertex_count),
        direct_(!stretchNewtonIsMatrixFree(n_, settings)),
        grid_phase_(!direct_ && settings.grid_max_steps > 0) {
    if (direct_) H_.resize(2 * n_, 2 * n_);
    if (grid_phase_) grid_.emplace(patch, frames, settings.grid);
    gradient.resize(2 * n_);
    direction.resize(2 * n_);
  }

  bool inGridPhase() const { return grid_phase_; }
  // After a step was taken (CheckedDescent::Outcome's halvings after the capped length).
  void adapt(double length, int halvings) {
    if (grid_) grid_->adapt(length, halvings);
  }
  // After a grid step that lowered the energy by the fraction `gain`: true when the next steps
  // take the finer grid (GridNewtonSystem::refineAfter).
  bool refineGrid(double gain) { return grid_ && grid_->refineAfter(gain); }
  int gridCells() const { return grid_ ? grid_->cells() : 0; }
  void leaveGridPhase() {
    grid_phase_ = false;
    grid_.reset();
  }

  // direction at `current` (whose energy is `energy`) and the energy's slope along it; false
  // when there is none.
  bool compute(const LocalUVs& current, const Energy& energy, CheckedDescent& descent,
               StretchNewtonCounts& counts, double& slope) {
    if (grid_phase_) {
      const bool usable = grid_->solve(current, energy, direction);
      descent.addWork(grid_->lastWork());
      slope = grid_->slope();
      ++counts.grid_steps;
      return usable && direction.allFinite();
    }
    if (!direct_) {
      if (!matrix_free_) {
        matrix_free_.emplace(patch_, frames_);
        descent.addWork(matrix_free_->spentWork());
      }
      const double before = matrix_free_->spentWork();
      const bool usable = matrix_free_->update(current, energy, gradient);
      if (usable)
        counts.cg_iterations += matrix_free_->solve(gradient, direction, settings_.cg_tolerance,
                                                    settings_.cg_max_iterations);
      descent.addWork(matrix_free_->spentWork() - before);
      slope = gradient.dot(direction);
      return usable && direction.allFinite();
    }
    assembleNewtonSystem(patch_, frames_, current, energy, gradient, entries_);
    H_.setFromTriplets(entries_.begin(), entries_.end());
    // The per-face terms, then 36 entries per face summed into the matrix.
    descent.addWork(patch_.real_face_count *
                    (WorkCosts::kNewtonHessianFace + 72 * WorkCosts::kNonzero));
    if (!factor_.factorize(H_)) return false;
    const double factor_work = factor_.lastWork();
    const bool solved = factor_.solve(-gradient, direction);
    descent.addWork(factor_work + factor_.lastWork());
    slope = gradient.dot(direction);
    return solved;
  }
  // Plain gradient descent, when the Newton direction does not descend (numerically).
  bool gradientDirection(double& slope) {
    if (grid_phase_) return false;
    direction = -gradient;
    slope = -gradient.squaredNorm();
    return slope < 0;
  }

  Eigen::VectorXd gradient, direction;

 private:
  const Patch& patch_;
  const std::vector<FaceFrame>& frames_;
  const StretchNewtonSettings& settings_;
  const int n_;
  const bool direct_;
  bool grid_phase_;
  std::optional<GridNewtonSystem> grid_;
  SymmetricFactor factor_;
  std::vector<Eigen::Triplet<double>> entries_;
  Eigen::SparseMatrix<double> H_;
  std::optional<AssembledNewtonSystem> matrix_free_;
};

// The descent's best map; no step counts as taken when it fell back to the start.
LocalUVs bestOf(CheckedDescent& descent, StretchNewtonCounts& counts) {
  LocalUVs best = descent.takeBest();
  if (descent.fellBack()) counts.steps_taken = 0;
  return best;
}

}  // namespace

double gridNewtonStepWork(int faces, int cells) {
  // The terms and products (kGridFaceWork), the collapse cap, one trial's energy and flip
  // check (its L2 comes from the energy); and the grid's factor, about 3e6 at 32 cells whatever
  // the patch's size and 3.6e7 at 64 (counted on face s1, s2 and s3, with most faces across
  // cell edges carrying their Hessian to one cell: GridNewtonSettings::exact_below): 2^3.6 per
  // doubling.
  return faces * (kGridFaceWork + WorkCosts::kFlipCheckFace * 2 + WorkCosts::kEnergyFace) +
         3e6 * std::pow(cells / 32.0, 3.6);
}

double firstFineNewtonStepWork(int faces) {
  // Counted at 414k vertices: 2000 units per face for the first step, 1230 for the next ones
  // (when each step also measured its metrics, 60 units per face of that).
  return faces * 2000.0;
}

namespace {

// The grid's steps first, then the fine ones, each with its own count (up to `steps` fine
// steps). A grid step that fails or stops gaining hands over to the fine steps; running out
// of budget ends both. `energy` is the current map's; `trial` receives each candidate's.
void takeNewtonSteps(const Patch& patch, const std::vector<FaceFrame>& frames, double total_area,
                     int steps, const StretchNewtonSettings& settings, NewtonDirection& newton,
                     CheckedDescent& descent, StretchNewtonCounts& counts, Energy& energy,
                     Energy& trial) {
  const int n = patch.real_vertex_count;
  const int faces = patch.real_face_count;
  LocalUVs& current = descent.current();
  Eigen::VectorXd& direction = newton.direction;
  LocalUVs step(current.size(), Eigen::Vector2d::Zero());
  const int grid_steps = newton.inGridPhase() ? settings.grid_max_steps : 0;
  int begun = 0;
  for (const bool grid : {true, false}) {
    if (grid != newton.inGridPhase()) continue;
    bool finished = false;  // the budget ran out, or the fine steps stopped
    for (int it = 0; it < (grid ? grid_steps : steps); ++it) {
      if (!descent.beginStep(begun++, grid_steps + steps)) {
        finished = true;
        break;
      }
      double slope = 0;
      if (!newton.compute(current, energy, descent, counts, slope) ||
          (!(slope < 0) && !newton.gradientDirection(slope))) {
        finished = counts.stopped = !grid;
        break;
      }
      for (int v = 0; v < n; ++v) step[v] = direction.segment<2>(2 * v);

      // Capped short of the first collapse, then halved until the energy drops enough; the
      // map is checked at the scale it is returned at.
      const auto sufficientDecrease = [&](LocalUVs& candidate, double length) {
        trial = energyOf(patch, frames, candidate);
        descent.addWork(faces * WorkCosts::kEnergyFace);
        if (!(trial.value() <= energy.value() + 1e-4 * length * slope)) return false;
        return rescaleToArea(candidate, n, total_area, trial);
      };
      const double length = std::min(1.0, 0.8 * stepBeforeCollapse(patch, current, step));
      descent.addWork(faces * WorkCosts::kFlipCheckFace);
      const CheckedDescent::Outcome outcome = descent.tryStep(step, length, 30, sufficientDecrease);
      if (!outcome.taken) {
        finished = counts.stopped = !grid;
        break;
      }
      ++counts.steps_taken;
      newton.adapt(length, outcome.halvings);
      const double before = energy.value();
      energy = trial;
      const double gain = outcome.gained ? 1 - energy.value() / before : 0;
      if (grid && newton.refineGrid(gain)) {
        descent.expectNextStepWork(gridNewtonStepWork(faces, newton.gridCells()));
        continue;
      }
      if (!outcome.gained) {
        finished = !grid;
        break;
      }
      if (!(energy.value() < before * (1 - 1e-9))) {  // converged as far as doubles tell
        finished = counts.stopped = !grid;
        break;
      }
    }
    if (grid) {
      newton.leaveGridPhase();
      descent.expectNextStepWork(settings.first_fine_step_work);
    }
    if (finished) break;
  }
}

}  // namespace

bool stretchNewtonIsMatrixFree(int vertices, const StretchNewtonSettings& settings) {
  return SolvePath(vertices, settings.direct_up_to).iterative();
}

LocalUVs minimizeStretchWithFreeBoundary(const Patch& patch, const LocalUVs& uv, int steps,
                                         StretchMetrics& metrics, StretchNewtonCounts& counts,
                                         const Progress& progress, const RefineBudget& budget,
                                         const StretchNewtonSettings& settings) {
  const int n = patch.real_vertex_count;
  const int faces = patch.real_face_count;
  if (steps <= 0 || n < 3 || faces == 0) return uv;
  if (budget.expired()) return uv;
  std::optional<CheckedDescent> descent;  // made inside the try: its allocations may fail too
  try {
    const double total_area = patchArea3d(patch);
    if (!(total_area > 0)) return uv;
    std::vector<FaceFrame> frames(faces);
    for (int f = 0; f < faces; ++f) frames[f] = faceFrame(patch, f, 1e-14 * total_area);
    descent.emplace(patch, uv, metrics, budget, progress, Stage::Newton);
    LocalUVs& current = descent->current();  // the best map stays `uv` until a step beats it
    Energy energy = energyOf(patch, frames, current);
    budget.charge(2.0 * faces * WorkCosts::kEnergyFace);  // the frames and the first energy
    if (!rescaleToArea(current, n, total_area, energy)) return uv;

    // L2^2 = Q S / (2 A^2) (stretch_newton.h): a step's L2 from its energy, the metrics once.
    const auto l2 = [total_area](const Energy& e) {
      return std::sqrt(e.Q * e.S / (2 * total_area * total_area));
    };
    Energy trial;  // a candidate's
    descent->measureL2By([&] { return l2(trial); }, l2(energy), uv);
    NewtonDirection newton(patch, frames, settings);
    takeNewtonSteps(patch, frames, total_area, steps, settings, newton, *descent, counts, energy,
                    trial);
    return bestOf(*descent, counts);
  } catch (const std::bad_alloc&) {
    counts.skipped = true;  // the system did not fit: keep the best map so far
    if (!descent) return uv;
    return bestOf(*descent, counts);
  }
}

}  // namespace sdp
