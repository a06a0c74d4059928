// The sparse matrix forms of core/linear: CSR rows, the split form (diagonal, strictly lower,
// strictly upper) the smoothers and Krylov loops read, and rectangular CSR for prolongations.
#pragma once

#include <cstddef>
#include <vector>

namespace sdp {

// Rows of a sparse matrix in CSR form.
struct CsrRows {
  std::vector<int> begin;  // rows + 1 starts into column/value
  std::vector<int> column;
  std::vector<double> value;
};

// Square sparse matrix kept as diagonal + strictly lower + strictly upper parts. The split lets
// a Gauss-Seidel sweep from zero read only the lower part and the residual after it only the
// upper part: one pass over the matrix instead of two in every cycle.
struct SplitCsr {
  int size = 0;
  std::vector<double> diagonal;
  CsrRows lower, upper;

  long long nonZeros() const {
    return static_cast<long long>(lower.column.size() + upper.column.size()) + size;
  }
  bool sameValues(const SplitCsr& other) const {
    return diagonal == other.diagonal && lower.value == other.lower.value &&
           upper.value == other.upper.value;
  }
  // Row-by-row building, the one way a SplitCsr is filled (the interior system from weights,
  // the scaled Laplacians from Eigen matrices, the Galerkin products): startRows(), then each
  // row's entries by add() and endRow(), rows in order. Diagonals not added keep `fill`.
  void startRows(int rows, double fill, size_t off_diagonal_reserve = 0) {
    size = rows;
    diagonal.assign(rows, fill);
    for (CsrRows* part : {&lower, &upper}) {
      part->begin.assign(rows + 1, 0);
      part->column.clear();
      part->value.clear();
      part->column.reserve(off_diagonal_reserve / 2);
      part->value.reserve(off_diagonal_reserve / 2);
    }
  }
  void add(int row, int col, double value) {
    if (col == row) {
      diagonal[row] = value;
      return;
    }
    CsrRows& part = col < row ? lower : upper;
    part.column.push_back(col);
    part.value.push_back(value);
  }
  void endRow(int row) {
    lower.begin[row + 1] = static_cast<int>(lower.column.size());
    upper.begin[row + 1] = static_cast<int>(upper.column.size());
  }
  template <class F>
  void forEachOffDiagonal(int i, F&& f) const {
    for (int k = lower.begin[i]; k < lower.begin[i + 1]; ++k) f(lower.column[k], lower.value[k]);
    for (int k = upper.begin[i]; k < upper.begin[i + 1]; ++k) f(upper.column[k], upper.value[k]);
  }
};

// Rectangular sparse matrix (prolongation and restriction).
struct Csr : CsrRows {
  int rows = 0, cols = 0;
};
Csr transposed(const Csr& M);

// y = A x on K interleaved columns.
template <int K>
void multiply(const SplitCsr& A, const double* x, double* y);

// y = A x with the column dots (y, w) and (y, y) taken on the way (core/linear/krylov.h's
// BiCGSTAB: the vector updates are memory-bound passes, and each fused dot saves one).
template <int K>
void multiplyWithDots(const SplitCsr& A, const double* x, double* y, const double* w, double* yw,
                      double* yy);

}  // namespace sdp
