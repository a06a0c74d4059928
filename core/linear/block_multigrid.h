// Multigrid for a symmetric positive definite system whose unknowns come in pairs (u and v of a
// vertex) coupled by 2x2 blocks: the Newton system of the stretch (stretch_newton.cpp). A scalar
// stand-in (one number per vertex pair, e.g. the mean of the u-u and v-v blocks) decides the
// aggregates and the smoothed prolongations (LaplacianMultigrid); the same prolongation moves u
// and v, and the coarse operators are the Galerkin products of the true 2x2 blocks, so the u-v
// coupling the stand-in drops is kept on every level. Block Gauss-Seidel smoothing, forward
// before the coarse correction and backward after: a symmetric cycle, as conjugate gradients
// need. A dense Cholesky factor solves the coarsest level.
//
// Numbering: BlockCsr rows are vertices; unknowns are interleaved, u of row i at 2i and v at
// 2i + 1. Each stored entry is a 2x2 block, row-major (uu, uv, vu, vv).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "laplacian_multigrid.h"
#include "multigrid.h"

namespace sdp {

struct BlockCsr {
  int size = 0;               // block rows (= block columns)
  std::vector<int> begin;     // size + 1 starts into column / 4 x value
  std::vector<int> column;    // block column of each entry, sorted within a row
  std::vector<double> value;  // 4 per entry, row-major
  std::vector<int> diagonal;  // entry index of each row's diagonal block
  long long blocks() const { return static_cast<long long>(column.size()); }
};

// y = A x on interleaved pairs.
void multiply(const BlockCsr& A, const double* x, double* y);

class BlockMultigrid {
 public:
  // The hierarchy for `fine`, numbered as `scalar`'s level 0, with its prolongations (kept by
  // reference: `scalar` must outlive this and keep its levels). Returns false when a diagonal
  // block is not positive definite.
  bool build(const Multigrid& scalar, BlockCsr fine);
  // The level-0 matrix, whose values may be changed in place (same pattern) before rebuild(),
  // which recomputes the coarse levels from them without new allocations.
  BlockCsr& fine() { return levels_.front().A; }
  bool rebuild();
  // x = one cycle applied to b (from a zero start).
  void cycle(const double* b, double* x) const;
  int levelCount() const { return static_cast<int>(levels_.size()); }
  // Work (work.h) of one cycle and of build().
  double cycleWork() const;
  double setupWork() const;

 private:
  struct Level {
    BlockCsr A;
    std::vector<Eigen::Matrix2d> inverse_diagonal;
    const Csr* P = nullptr;  // the scalar hierarchy's prolongation from the next level
    Csr R;                   // its transpose
  };
  void cycleFrom(int level, const double* b, double* x) const;
  bool factor();  // diagonal inverses and the coarsest Cholesky factor

  std::vector<Level> levels_;
  Eigen::LLT<Eigen::MatrixXd> coarsest_;
  mutable std::vector<std::vector<double>> x_, b_, r_;  // per level scratch
};

// The Newton system's preconditioner: a scalar stand-in's hierarchy (LaplacianMultigrid, its
// breadth-first order and diagonal scaling) carrying a BlockMultigrid of the true blocks.
class CoupledMultigrid {
 public:
  // `proxy`: the n x n symmetric stand-in (column-major, compressed). `blocks`: 4 values per
  // nonzero of `proxy`, in its storage order, the 2x2 block of the system at that (row, column).
  // The stand-in's hierarchy is built on the first call and kept (the pattern must stay);
  // each call rebuilds the block hierarchy. Returns whether both could be built.
  bool update(const Eigen::SparseMatrix<double>& proxy, const std::vector<double>& blocks);
  // z = one cycle for H z = r, on u and v interleaved per vertex (r[2i], r[2i + 1]).
  void applyCycle(const double* r, double* z) const;
  // Work (work.h) of every update and cycle so far.
  double spentWork() const { return scalar_.spentWork() + spent_work_; }

 private:
  // The fine block matrix's rows and columns (values to fill) in the stand-in's numbering;
  // sets slot_entry_ and slot_scale_.
  BlockCsr numberBlocks(const Eigen::SparseMatrix<double>& proxy);

  LaplacianMultigrid scalar_;
  BlockMultigrid blocks_;
  std::vector<int> slot_entry_;     // per nonzero of the stand-in: its entry in the fine level
  std::vector<double> slot_scale_;  // ... and its diagonal scaling
  mutable double spent_work_ = 0;
};

}  // namespace sdp
