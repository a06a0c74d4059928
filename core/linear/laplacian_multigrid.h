// The project's multigrid (multigrid.h) for a symmetric matrix L with a positive diagonal and
// non-positive off-diagonal entries (a weighted graph Laplacian, plus a diagonal): the rows are
// put in breadth-first order (neighbours close in memory, as in solve.cpp) and scaled on both
// sides by the diagonal's square root, which gives the unit-diagonal M-matrix the hierarchy is
// built for and keeps it symmetric (dividing rows alone made coarse diagonals negative where
// the diagonal varies 50-fold, as in the Newton proxy). Used to
// solve the ARAP global step (free_boundary.cpp) and to precondition the Newton steps on large
// patches (stretch_newton.cpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "core/common/work.h"
#include "multigrid.h"

namespace sdp {

class LaplacianMultigrid {
 public:
  // Builds the hierarchy for L (n x n, symmetric pattern). Returns usable().
  bool build(const Eigen::SparseMatrix<double>& L);
  // New values on the pattern build() saw: keeps the aggregates (Multigrid's
  // rebuildWithSameAggregates). Returns usable().
  bool update(const Eigen::SparseMatrix<double>& L);
  // False when a row had no positive diagonal or coarsening stalled.
  bool usable() const { return usable_; }

  // Solves L x = b (L symmetric positive definite: conjugate gradients, x is the start) to the
  // relative residual `tolerance`; false when
  // it did not converge within `max_iterations`.
  bool solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, double tolerance,
             int max_iterations) const;
  // z = one multigrid cycle for L z = r on two columns interleaved per row (r[2i], r[2i + 1]):
  // an approximate inverse of L on u and v at once.
  void applyCycle(const double* r, double* z) const;
  // The hierarchy on the scaled matrix A = S^-1 L S^-1 in breadth-first numbering: row p of A is
  // row order()[p] of L, and S = diag(rootDiagonal()) in L's numbering.
  const Multigrid& hierarchy() const { return multigrid_; }
  const std::vector<int>& order() const { return order_; }
  const std::vector<double>& rootDiagonal() const { return root_diagonal_; }
  // Work (work.h) of all the calls so far: setup, iterations, cycles.
  double spentWork() const { return spent_work_; }

  // z = S^-1 y with y = apply(S^-1 r) taken in the hierarchy's numbering: r and z in L's, two
  // columns interleaved per row; apply(in, out) sees breadth-first rows of the scaled matrix.
  // Counts the two passes' work; apply counts its own.
  template <class Apply>
  void applyScaled(const double* r, double* z, Apply&& apply) const {
    const int n = static_cast<int>(order_.size());
    in_.resize(2 * static_cast<size_t>(n));
    out_.resize(2 * static_cast<size_t>(n));
    for (int p = 0; p < n; ++p) {
      const int i = order_[p];
      in_[2 * p] = r[2 * i] / root_diagonal_[i];
      in_[2 * p + 1] = r[2 * i + 1] / root_diagonal_[i];
    }
    apply(static_cast<const double*>(in_.data()), out_.data());
    for (int p = 0; p < n; ++p) {
      const int i = order_[p];
      z[2 * i] = out_[2 * p] / root_diagonal_[i];
      z[2 * i + 1] = out_[2 * p + 1] / root_diagonal_[i];
    }
    spent_work_ += 4.0 * n * WorkCosts::kVectorEntry;
  }

 private:
  void orderBreadthFirst(const Eigen::SparseMatrix<double>& L);  // sets order_
  // A = L in order_, scaled to a unit diagonal; false when a diagonal entry is not positive.
  bool scale(const Eigen::SparseMatrix<double>& L, SplitCsr& A);

  std::vector<int> order_;             // breadth-first position -> row of L
  std::vector<double> root_diagonal_;  // square root of L's diagonal, per row
  Multigrid multigrid_;
  bool usable_ = false;
  mutable MultigridWorkspace work_;
  mutable std::vector<double> in_, out_;  // applyCycle's vectors in breadth-first order
  mutable double spent_work_ = 0;
};

}  // namespace sdp
