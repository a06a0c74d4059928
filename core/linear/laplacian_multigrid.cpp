#include "laplacian_multigrid.h"

#include <cmath>

#include "core/common/work.h"
#include "krylov.h"
#include "ordering.h"

namespace sdp {

void LaplacianMultigrid::orderBreadthFirst(const Eigen::SparseMatrix<double>& L) {
  order_ = breadthFirstOrder(
      static_cast<int>(L.rows()), {}, [](int) { return true; },
      [&](int v, auto&& visit) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, v); it; ++it)
          visit(static_cast<int>(it.row()));
      });
}

namespace {
// Reordering and scaling L: about one sparse pass with scattered reads.
double scaleWork(const Eigen::SparseMatrix<double>& L) {
  return 4.0 * static_cast<double>(L.nonZeros()) * WorkCosts::kNonzero;
}
}  // namespace

bool LaplacianMultigrid::scale(const Eigen::SparseMatrix<double>& L, SplitCsr& A) {
  const int n = static_cast<int>(L.rows());
  std::vector<int> new_of(n);
  for (int r = 0; r < n; ++r) new_of[order_[r]] = r;
  root_diagonal_.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, i); it; ++it)
      if (it.row() == i) root_diagonal_[i] = std::sqrt(it.value());
    if (!(root_diagonal_[i] > 0)) return false;
  }
  A.startRows(n, 1.0);
  for (int r = 0; r < n; ++r) {
    const int i = order_[r];
    // Columns of the symmetric L serve as its rows.
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, i); it; ++it) {
      if (it.row() == i) continue;
      A.add(r, new_of[it.row()], it.value() / (root_diagonal_[i] * root_diagonal_[it.row()]));
    }
    A.endRow(r);
  }
  return true;
}

bool LaplacianMultigrid::build(const Eigen::SparseMatrix<double>& L) {
  usable_ = false;
  multigrid_ = Multigrid();
  work_ = MultigridWorkspace();
  orderBreadthFirst(L);
  SplitCsr A;
  if (!scale(L, A)) return false;
  multigrid_.build(std::move(A));
  spent_work_ += multigrid_.setupWork(false) + scaleWork(L);
  usable_ = multigrid_.usable();
  return usable_;
}

bool LaplacianMultigrid::update(const Eigen::SparseMatrix<double>& L) {
  if (multigrid_.empty() || static_cast<int>(order_.size()) != L.rows()) return build(L);
  SplitCsr A;
  usable_ = false;
  if (!scale(L, A)) return false;
  multigrid_.rebuildWithSameAggregates(std::move(A));
  spent_work_ += multigrid_.setupWork(true) + scaleWork(L);
  usable_ = multigrid_.usable();
  return usable_;
}

// With S = diag(L)^(1/2), L x = b is A y = S^-1 b with A = S^-1 L S^-1 and x = S^-1 y.
bool LaplacianMultigrid::solve(const Eigen::MatrixX2d& b, Eigen::MatrixX2d& x, double tolerance,
                               int max_iterations) const {
  const int n = static_cast<int>(order_.size());
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> bn(n, 2), yn(n, 2);
  for (int r = 0; r < n; ++r) {
    const int i = order_[r];
    bn.row(r) = b.row(i) / root_diagonal_[i];
    yn.row(r) = x.row(i) * root_diagonal_[i];
  }
  const KrylovOutcome outcome =
      solveConjugateGradients<2>(multigrid_, bn.data(), yn.data(), tolerance, max_iterations);
  // Per iteration one cycle, one product and five vector passes (u and v); the true residuals.
  const double iteration_work = multigrid_.cycleWork() +
                                multigrid_.fine().nonZeros() * WorkCosts::kNonzero +
                                5.0 * n * WorkCosts::kVectorEntry;
  spent_work_ += outcome.iterations * iteration_work +
                 2.0 * multigrid_.fine().nonZeros() * WorkCosts::kNonzero +
                 4.0 * n * WorkCosts::kVectorEntry;
  if (!outcome.converged) return false;
  for (int r = 0; r < n; ++r) x.row(order_[r]) = yn.row(r) / root_diagonal_[order_[r]];
  return true;
}

void LaplacianMultigrid::applyCycle(const double* r, double* z) const {
  if (static_cast<int>(work_.x.size()) != multigrid_.levelCount())
    work_ = multigrid_.makeWorkspace(2);
  applyScaled(r, z, [&](const double* in, double* out) { multigrid_.cycle<2>(in, out, work_); });
  spent_work_ += multigrid_.cycleWork();
}

}  // namespace sdp
