#include "free_boundary.h"

#include "checked_descent.h"
#include "core/common/geometry.h"
#include "core/common/work.h"
#include "core/linear/laplacian_multigrid.h"
#include "core/linear/solve_path.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>

namespace sdp {

std::array<Eigen::Vector2d, 3> flatTriangle(const Patch& patch, int f) {
  const auto& t = patch.face[f];
  const Eigen::Vector3d e1 = patch.position[t[1]] - patch.position[t[0]];
  const Eigen::Vector3d e2 = patch.position[t[2]] - patch.position[t[0]];
  const double l1 = e1.norm();
  std::array<Eigen::Vector2d, 3> x;
  x[0] = Eigen::Vector2d::Zero();
  x[1] = Eigen::Vector2d(l1, 0);
  x[2] =
      l1 > 0 ? Eigen::Vector2d(e1.dot(e2) / l1, e1.cross(e2).norm() / l1) : Eigen::Vector2d::Zero();
  return x;
}

namespace {

// The 3D triangle laid flat and its cotangent weights: weight[k] belongs to the edge opposite
// corner k.
struct FlatFace {
  std::array<Eigen::Vector2d, 3> x;
  std::array<double, 3> weight;
};

FlatFace flatten(const Patch& patch, int f) {
  FlatFace flat;
  flat.x = flatTriangle(patch, f);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d u = flat.x[(k + 1) % 3] - flat.x[k], v = flat.x[(k + 2) % 3] - flat.x[k];
    const double cross = std::abs(cross2(u, v));
    // Cotangent weights kept in [0.01, 1e4]: positive, so the global step is an M-matrix the
    // project's multigrid solves in a few iterations (exact cotangents, negative at obtuse
    // angles, need a Cholesky factor, several times slower: docs/measurements.md), and a
    // needle's huge cotangent cannot swamp the system. Any positive weights give a valid
    // local/global descent; on the shared meshes the stretch reached was the same to 3 digits.
    constexpr double kLow = 0.01, kHigh = 1e4;
    const double cot = cross > 0 ? u.dot(v) / cross : kHigh;
    flat.weight[k] = 0.5 * std::clamp(cot, kLow, kHigh);
  }
  return flat;
}

// Solves L x = b for the global step, L fixed across steps (symmetric, positive weights, one
// vertex pinned): conjugate gradients with the project's multigrid from the previous positions
// (a step moves them a little); an LDLT factor for small systems or when the iteration does not
// converge (linear/solve_path.h).
class GlobalSolver {
 public:
  // Built here from its entries: a copied Eigen::SparseMatrix leaks its index array when the
  // copy's second allocation fails (the allocation-failure tests found it).
  GlobalSolver(int n, const std::vector<Eigen::Triplet<double>>& entries)
      : path_(n, DirectUpTo::kArapGlobalStep) {
    L_.resize(n, n);
    L_.setFromTriplets(entries.begin(), entries.end());
    if (!path_.iterative()) return;
    if (!multigrid_.build(L_)) path_.fallBack();
    spent_work_ = multigrid_.spentWork();
  }

  bool solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x) {
    if (path_.iterative()) {
      const double before = multigrid_.spentWork();
      const bool solved = multigrid_.solve(b, x, 1e-8, 100);
      spent_work_ += multigrid_.spentWork() - before;
      if (solved) return true;
      path_.fallBack();
      multigrid_ = LaplacianMultigrid();
    }
    if (!factor_.factored()) {
      if (!factor_.factorize(L_)) return false;
      spent_work_ += factor_.lastWork();
    }
    const bool solved = factor_.solve(b, x);
    spent_work_ += factor_.lastWork();
    return solved;
  }
  // Work (work.h) of the setup and every solve so far.
  double spentWork() const { return spent_work_; }

 private:
  Eigen::SparseMatrix<double> L_;
  SolvePath path_;
  LaplacianMultigrid multigrid_;
  SymmetricFactor factor_;
  double spent_work_ = 0;
};

// The ARAP local step and the global step's right-hand side: the rotation closest to each
// face's current map (2x2 polar decomposition in closed form), then the rotated flat edges summed
// per vertex, vertex `pinned` (row-less) moved to the right-hand side.
void arapRightHandSide(const Patch& patch, const std::vector<FlatFace>& flat,
                       const LocalUVs& current, int pinned, Eigen::MatrixX2d& rhs) {
  auto unknown = [&](int v) { return v < pinned ? v : v - 1; };
  const int faces = patch.real_face_count;
  rhs.setZero();
  for (int f = 0; f < faces; ++f) {
    const auto& t = patch.face[f];
    Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      S += flat[f].weight[k] * (current[t[a]] - current[t[b]]) *
           (flat[f].x[a] - flat[f].x[b]).transpose();
    }
    const double angle = std::atan2(S(1, 0) - S(0, 1), S(0, 0) + S(1, 1));
    Eigen::Matrix2d R;
    R << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const int i = t[a], j = t[b];
      const Eigen::Vector2d target = flat[f].weight[k] * (R * (flat[f].x[a] - flat[f].x[b]));
      if (i != pinned) {
        rhs.row(unknown(i)) += target.transpose();
        if (j == pinned) rhs.row(unknown(i)) += flat[f].weight[k] * current[j].transpose();
      }
      if (j != pinned) {
        rhs.row(unknown(j)) -= target.transpose();
        if (i == pinned) rhs.row(unknown(j)) += flat[f].weight[k] * current[i].transpose();
      }
    }
  }
}

}  // namespace

LocalUVs relaxWithFreeBoundary(const Patch& patch, const LocalUVs& uv, int steps,
                               StretchMetrics& metrics, FreeBoundaryCounts& counts,
                               const Progress& progress, const RefineBudget& budget) {
  const int n = patch.real_vertex_count;
  const int faces = patch.real_face_count;
  if (steps <= 0 || n < 3 || faces == 0) return uv;
  if (budget.expired()) return uv;  // before the setup, which costs about a step itself
  try {
    // Start at the 3D size (the rigid targets are 3D edge vectors); the best map stays the
    // start as given until a step lowers L2.
    const double area2d = patchAreaUV(patch, uv), area3d = patchArea3d(patch);
    if (!(area2d > 0) || !(area3d > 0)) return uv;
    const double scale = std::sqrt(area3d / area2d);
    CheckedDescent descent(patch, uv, metrics, budget, progress, Stage::FreeBoundary);
    for (auto& p : descent.current()) p *= scale;

    std::vector<FlatFace> flat(faces);
    for (int f = 0; f < faces; ++f) flat[f] = flatten(patch, f);

    // Global step matrix: the weighted Laplacian over the real vertices, vertex 0 pinned (the
    // energy does not see translations). Set up once, used by every step.
    const int pinned = 0;
    auto unknown = [&](int v) { return v < pinned ? v : v - 1; };
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(faces) * 12);
    for (int f = 0; f < faces; ++f)
      for (int k = 0; k < 3; ++k) {
        const int i = patch.face[f][(k + 1) % 3], j = patch.face[f][(k + 2) % 3];
        const double w = flat[f].weight[k];
        if (i != pinned) entries.emplace_back(unknown(i), unknown(i), w);
        if (j != pinned) entries.emplace_back(unknown(j), unknown(j), w);
        if (i != pinned && j != pinned) {
          entries.emplace_back(unknown(i), unknown(j), -w);
          entries.emplace_back(unknown(j), unknown(i), -w);
        }
      }
    GlobalSolver global(n - 1, entries);
    std::vector<Eigen::Triplet<double>>().swap(entries);
    // The setup: flat faces, the matrix from its 12 entries per face, the solver's hierarchy.
    budget.charge(faces * (WorkCosts::kArapLocalFace + 24 * WorkCosts::kNonzero) +
                  global.spentWork());
    Eigen::MatrixX2d solved(n - 1, 2);
    Eigen::MatrixX2d rhs(n - 1, 2);
    LocalUVs direction(uv.size(), Eigen::Vector2d::Zero());  // the pinned vertex stays

    int steps_without_gain = 0;  // L2 is not what ARAP lowers: allow one step that does not
    for (int step = 0; step < steps; ++step) {
      if (!descent.beginStep(step, steps)) break;
      const LocalUVs& current = descent.current();
      // Local step, then the global step: the positions that best fit all the rotated faces.
      arapRightHandSide(patch, flat, current, pinned, rhs);
      for (int v = 0; v < n; ++v)
        if (v != pinned) solved.row(unknown(v)) = current[v].transpose();
      const double solver_work = global.spentWork();
      const bool solved_ok = global.solve(rhs, solved);
      descent.addWork(faces * WorkCosts::kArapLocalFace + global.spentWork() - solver_work);
      if (!solved_ok) break;
      for (int v = 0; v < n; ++v)
        if (v != pinned) direction[v] = solved.row(unknown(v)).transpose() - current[v];

      // The whole step, halved until it neither folds a face nor crosses the boundary.
      const CheckedDescent::Outcome outcome = descent.tryStep(direction, 1.0, 8);
      if (outcome.taken) {
        ++counts.steps_taken;
        if (outcome.halvings > 0) ++counts.steps_shortened;
        steps_without_gain = outcome.gained ? 0 : steps_without_gain + 1;
      }
      if (steps_without_gain >= 2) break;
      if (!outcome.taken) {
        counts.stopped = true;
        break;
      }
    }
    return descent.takeBest();
  } catch (const std::bad_alloc&) {
    counts.stopped = true;  // the factor did not fit: keep the fixed-boundary map
    return uv;
  }
}

}  // namespace sdp
