#include "solve.h"

#include <chrono>
#include <string>

#include "core/common/error.h"
#include "core/common/parallel.h"
#include "core/common/work.h"
#include "core/linear/krylov.h"
#include "core/linear/ordering.h"

namespace sdp {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

InteriorSolver::InteriorSolver(const Patch& patch, const SolverSettings& settings)
    : patch_(patch), settings_(settings), unknown_(patch.vertexCount(), -1) {
  // Unknowns in breadth-first order over the interior (core/linear/ordering.h), starting next to
  // the boundary: that keeps the fronts, and so the bandwidth, short.
  std::vector<int> first_front;
  if (patch.interiorCount() > 0) {
    const int b = patch.boundary_loop.empty() ? 0 : patch.boundary_loop.front();
    first_front.assign(patch.ring_vertex.begin() + patch.ring_begin[b],
                       patch.ring_vertex.begin() + patch.ring_begin[b + 1]);
  }
  interior_vertex_ = breadthFirstOrder(
      patch.vertexCount(), first_front, [&](int v) { return !patch.on_boundary[v]; },
      [&](int v, auto&& visit) {
        for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k)
          visit(patch.ring_vertex[k]);
      });
  for (int v : interior_vertex_) unknown_[v] = unknowns_++;
  path_ = SolvePath(unknowns_, settings_.direct_up_to, settings_.method);
}

void InteriorSolver::assemble(const std::vector<double>& weights, const LocalUVs& uv, SplitCsr& A,
                              RightHandSides& rhs) const {
  const Patch& p = patch_;
  A.startRows(unknowns_, 1.0, p.ring_vertex.size());
  rhs = RightHandSides::Zero(unknowns_, 2);
  for (int row = 0; row < unknowns_; ++row) {
    const int v = interior_vertex_[row];
    for (int k = p.ring_begin[v]; k < p.ring_begin[v + 1]; ++k) {
      const int j = unknown_[p.ring_vertex[k]];
      if (j >= 0) {
        A.add(row, j, -weights[k]);
      } else {
        rhs.row(row) += weights[k] * uv[p.ring_vertex[k]].transpose();
      }
    }
    A.endRow(row);
  }
}

LocalUVs InteriorSolver::solve(const std::vector<double>& weights, const Polygon& boundary) {
  const auto start = Clock::now();
  stats_ = SolverStats{};
  const Patch& p = patch_;
  LocalUVs uv(p.vertexCount(), Eigen::Vector2d::Zero());
  for (size_t k = 0; k < p.boundary_loop.size(); ++k) uv[p.boundary_loop[k]] = boundary[k];
  if (unknowns_ == 0) return uv;

  SplitCsr A;
  RightHandSides rhs, x;
  assemble(weights, uv, A, rhs);
  const double assembly_work = 2.0 * p.ring_vertex.size() * WorkCosts::kNonzero;
  stats_.work = assembly_work;
  if (path_.iterative()) {
    stats_.multigrid = true;
    if (!solveIteratively(std::move(A), rhs, x)) {
      // LU from now on: a system this solver could not converge on will not get easier with the
      // next weights. The hierarchy goes first, to make room for the factors.
      stats_.fell_back = true;
      path_.fallBack();
      multigrid_ = Multigrid();
      previous_.resize(0, 2);
      assemble(weights, uv, A, rhs);
      stats_.work += assembly_work;
      solveDirectly(A, rhs, x);
    }
  } else {
    solveDirectly(A, rhs, x);
  }
  if (!x.allFinite()) throw ParameterizationError("the linear solve failed (non-finite result)");
  for (int v = 0; v < p.vertexCount(); ++v)
    if (unknown_[v] >= 0) uv[v] = x.row(unknown_[v]).transpose();
  stats_.solve_seconds = secondsSince(start) - stats_.setup_seconds;
  return uv;
}

bool InteriorSolver::solveIteratively(SplitCsr A, const RightHandSides& rhs, RightHandSides& x) {
  const auto start = Clock::now();
  if (!multigrid_.empty() && A.sameValues(multigrid_.fine())) {
    stats_.reused_hierarchy = true;  // same weights (e.g. a new boundary): only b changed
  } else if (!multigrid_.empty()) {
    multigrid_.rebuildWithSameAggregates(std::move(A));
    stats_.reused_hierarchy = true;
    stats_.work += multigrid_.setupWork(true);
  } else {
    multigrid_.build(std::move(A), settings_.multigrid);
    stats_.work += multigrid_.setupWork(false);
  }
  if (!multigrid_.usable()) return false;
  stats_.levels = multigrid_.levelCount();
  stats_.operator_complexity = multigrid_.operatorComplexity();
  stats_.hierarchy_bytes = multigrid_.memoryBytes();
  stats_.setup_seconds = secondsSince(start);

  // Start from the previous solution where it is closer than zero (refinement iterations move
  // the map only a little; a new boundary usually moves it a lot).
  x = RightHandSides::Zero(unknowns_, 2);
  if (previous_.rows() == unknowns_) {
    RightHandSides r(unknowns_, 2);
    multiply<2>(multigrid_.fine(), previous_.data(), r.data());
    r = rhs - r;
    for (int c = 0; c < 2; ++c)
      if (r.col(c).norm() < rhs.col(c).norm()) x.col(c) = previous_.col(c);
  }

  KrylovOutcome outcome;
  if (settings_.parallel_columns) {
    Eigen::VectorXd b[2] = {rhs.col(0), rhs.col(1)}, xc[2] = {x.col(0), x.col(1)};
    KrylovOutcome column[2];
    parallelFor(2, 1, [&](int first, int last, int) {
      for (int c = first; c < last; ++c)
        column[c] = solveBiCgStab<1>(multigrid_, b[c].data(), xc[c].data(), settings_.tolerance,
                                     settings_.max_iterations);
    });
    x.col(0) = xc[0];
    x.col(1) = xc[1];
    outcome.iterations = std::max(column[0].iterations, column[1].iterations);
    outcome.relative_residual = std::max(column[0].relative_residual, column[1].relative_residual);
    outcome.converged = column[0].converged && column[1].converged;
  } else {
    outcome = solveBiCgStab<2>(multigrid_, rhs.data(), x.data(), settings_.tolerance,
                               settings_.max_iterations);
  }
  stats_.iterations = outcome.iterations;
  stats_.relative_residual = outcome.relative_residual;
  stats_.work += (outcome.iterations + 1) * multigrid_.iterationWork();
  if (!outcome.converged) return false;
  previous_ = x;
  return true;
}

bool InteriorSolver::tighten() {
  if (!stats_.multigrid || stats_.fell_back || settings_.tolerance <= settings_.tight_tolerance)
    return false;
  settings_.tolerance = settings_.tight_tolerance;
  return true;
}

void InteriorSolver::loosen(double tolerance) {
  if (tolerance > settings_.tolerance && settings_.tolerance > settings_.tight_tolerance)
    settings_.tolerance = tolerance;
}

void InteriorSolver::solveDirectly(const SplitCsr& A, const RightHandSides& rhs,
                                   RightHandSides& x) {
  const auto start = Clock::now();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(A.nonZeros());
  for (int i = 0; i < A.size; ++i) {
    entries.emplace_back(i, i, A.diagonal[i]);
    A.forEachOffDiagonal(i, [&](int j, double a) { entries.emplace_back(i, j, a); });
  }
  Eigen::SparseMatrix<double> M(A.size, A.size);
  M.setFromTriplets(entries.begin(), entries.end());
  M.makeCompressed();
  std::vector<Eigen::Triplet<double>>().swap(entries);
  if (!analyzed_) {
    lu_.analyzePattern(M);
    analyzed_ = true;
  }
  lu_.factorize(M);
  if (lu_.info() != Eigen::Success)
    throw ParameterizationError("the linear system could not be factored: " +
                                lu_.lastErrorMessage());
  // A factorization's multiply-adds are about the sum over columns of (column count)^2, which
  // for counts near the mean is nnz^2 / n; back-substitution visits each factor entry twice.
  const double factor_nonzeros = static_cast<double>(lu_.nnzL() + lu_.nnzU());
  stats_.work += WorkCosts::kFactorFlop * factor_nonzeros * factor_nonzeros / A.size +
                 4 * factor_nonzeros * WorkCosts::kNonzero;
  stats_.setup_seconds += secondsSince(start);
  const Eigen::MatrixX2d b = rhs;
  const Eigen::MatrixX2d solution = lu_.solve(b);
  x = solution;
  if (lu_.info() != Eigen::Success)
    throw ParameterizationError("the linear solve failed (non-finite result)");
  RightHandSides Ax(A.size, 2);
  multiply<2>(A, x.data(), Ax.data());
  const Eigen::MatrixX2d r = b - Eigen::MatrixX2d(Ax);
  stats_.relative_residual = std::max(r.col(0).norm() / std::max(b.col(0).norm(), 1e-300),
                                      r.col(1).norm() / std::max(b.col(1).norm(), 1e-300));
}

}  // namespace sdp
