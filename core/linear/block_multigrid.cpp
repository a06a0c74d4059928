#include "block_multigrid.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "core/common/parallel.h"
#include "core/common/work.h"

namespace sdp {
namespace {

using Block = Eigen::Matrix2d;

Block blockAt(const BlockCsr& A, int k) {
  const double* v = &A.value[4 * static_cast<size_t>(k)];
  Block b;
  b << v[0], v[1], v[2], v[3];
  return b;
}

// x_i += sign * sum_k A_ik x_k over the entries of row i that `take` admits.
template <class Take>
Eigen::Vector2d rowTimes(const BlockCsr& A, int i, const double* x, Take&& take) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int k = A.begin[i]; k < A.begin[i + 1]; ++k) {
    const int j = A.column[k];
    if (!take(j)) continue;
    const double* v = &A.value[4 * static_cast<size_t>(k)];
    sum.x() += v[0] * x[2 * j] + v[1] * x[2 * j + 1];
    sum.y() += v[2] * x[2 * j] + v[3] * x[2 * j + 1];
  }
  return sum;
}

// A_c = R A P for blocks A and scalar P (R = P^T): coarse row c sums r_ci A_ij p_jd, first
// over i into a fine accumulator w_j, then w P. `into` (may be null): a matrix with the
// product's pattern, whose values are overwritten instead (a rebuild: nothing allocated).
BlockCsr galerkin(const BlockCsr& A, const Csr& P, const Csr& R, BlockCsr* into = nullptr) {
  const int nc = R.rows;
  std::vector<BlockCsr> chunk(parallelWorkers());
  parallelFor(nc, 1024, [&](int first, int last, int worker) {
    BlockCsr& out = chunk[worker];
    out.begin.push_back(0);
    std::vector<Block> fine(A.size, Block::Zero()), coarse(nc, Block::Zero());
    std::vector<int> fine_mark(A.size, -1), fine_touched, mark(nc, -1), touched;
    for (int c = first; c < last; ++c) {
      fine_touched.clear();
      touched.clear();
      for (int k = R.begin[c]; k < R.begin[c + 1]; ++k) {
        const int i = R.column[k];
        const double r = R.value[k];
        for (int e = A.begin[i]; e < A.begin[i + 1]; ++e) {
          const int j = A.column[e];
          if (fine_mark[j] != c) {
            fine_mark[j] = c;
            fine_touched.push_back(j);
            fine[j] = r * blockAt(A, e);
          } else {
            fine[j] += r * blockAt(A, e);
          }
        }
      }
      for (int j : fine_touched)
        for (int k = P.begin[j]; k < P.begin[j + 1]; ++k) {
          const int d = P.column[k];
          if (mark[d] != c) {
            mark[d] = c;
            touched.push_back(d);
            coarse[d] = P.value[k] * fine[j];
          } else {
            coarse[d] += P.value[k] * fine[j];
          }
        }
      if (into) {  // the pattern's row c holds exactly the touched columns, sorted
        for (int k = into->begin[c]; k < into->begin[c + 1]; ++k) {
          const Block& b = coarse[into->column[k]];
          double* v = &into->value[4 * static_cast<size_t>(k)];
          v[0] = b(0, 0), v[1] = b(0, 1), v[2] = b(1, 0), v[3] = b(1, 1);
        }
        continue;
      }
      std::sort(touched.begin(), touched.end());
      for (int d : touched) {
        out.column.push_back(d);
        const Block& b = coarse[d];
        out.value.insert(out.value.end(), {b(0, 0), b(0, 1), b(1, 0), b(1, 1)});
      }
      out.begin.push_back(static_cast<int>(out.column.size()));
    }
  });
  if (into) return {};
  // The chunks are contiguous row ranges in order: concatenated, they are the same matrix
  // whatever the number of cores.
  BlockCsr Ac;
  Ac.size = nc;
  Ac.begin.assign(1, 0);
  for (const BlockCsr& part : chunk) {
    if (part.begin.empty()) continue;
    const int offset = static_cast<int>(Ac.column.size());
    for (size_t r = 1; r < part.begin.size(); ++r) Ac.begin.push_back(offset + part.begin[r]);
    Ac.column.insert(Ac.column.end(), part.column.begin(), part.column.end());
    Ac.value.insert(Ac.value.end(), part.value.begin(), part.value.end());
  }
  return Ac;
}

bool findDiagonal(BlockCsr& A) {
  A.diagonal.assign(A.size, -1);
  for (int i = 0; i < A.size; ++i)
    for (int k = A.begin[i]; k < A.begin[i + 1]; ++k)
      if (A.column[k] == i) A.diagonal[i] = k;
  return std::find(A.diagonal.begin(), A.diagonal.end(), -1) == A.diagonal.end();
}

}  // namespace

void multiply(const BlockCsr& A, const double* x, double* y) {
  for (int i = 0; i < A.size; ++i) {
    const Eigen::Vector2d s = rowTimes(A, i, x, [](int) { return true; });
    y[2 * i] = s.x();
    y[2 * i + 1] = s.y();
  }
}

bool BlockMultigrid::build(const Multigrid& scalar, BlockCsr fine) {
  levels_.clear();
  levels_.emplace_back();
  levels_.back().A = std::move(fine);
  for (int l = 0; l + 1 < scalar.levelCount(); ++l) {
    Level& level = levels_[l];
    level.P = &scalar.prolongation(l);
    level.R = transposed(*level.P);
    BlockCsr coarse = galerkin(level.A, *level.P, level.R);
    levels_.emplace_back();
    levels_.back().A = std::move(coarse);
  }
  for (Level& level : levels_)
    if (!findDiagonal(level.A)) return false;
  x_.resize(levels_.size());
  b_.resize(levels_.size());
  r_.resize(levels_.size());
  for (size_t l = 0; l < levels_.size(); ++l) {
    const size_t n = 2 * static_cast<size_t>(levels_[l].A.size);
    x_[l].assign(n, 0.0);
    b_[l].assign(n, 0.0);
    r_[l].assign(n, 0.0);
  }
  return factor();
}

bool BlockMultigrid::rebuild() {
  for (int l = 0; l + 1 < levelCount(); ++l)
    galerkin(levels_[l].A, *levels_[l].P, levels_[l].R, &levels_[l + 1].A);
  return factor();
}

bool BlockMultigrid::factor() {
  for (Level& level : levels_) {
    level.inverse_diagonal.resize(level.A.size);
    for (int i = 0; i < level.A.size; ++i) {
      const Block d = blockAt(level.A, level.A.diagonal[i]);
      if (!(d(0, 0) > 0) || !(d.determinant() > 0)) return false;
      level.inverse_diagonal[i] = d.inverse();
    }
  }
  const BlockCsr& last = levels_.back().A;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(2 * last.size, 2 * last.size);
  for (int i = 0; i < last.size; ++i)
    for (int k = last.begin[i]; k < last.begin[i + 1]; ++k)
      dense.block<2, 2>(2 * i, 2 * last.column[k]) = blockAt(last, k);
  coarsest_.compute(dense);
  return coarsest_.info() == Eigen::Success;
}

void BlockMultigrid::cycle(const double* b, double* x) const {
  cycleFrom(0, b, x);
}

void BlockMultigrid::cycleFrom(int l, const double* b, double* x) const {
  const Level& L = levels_[l];
  const int n = L.A.size;
  if (l + 1 == levelCount()) {
    const Eigen::Map<const Eigen::VectorXd> rhs(b, 2 * n);
    Eigen::Map<Eigen::VectorXd>(x, 2 * n) = coarsest_.solve(rhs);
    return;
  }
  // Forward Gauss-Seidel from zero: only the entries left of the diagonal see a nonzero x.
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d s =
        Eigen::Vector2d(b[2 * i], b[2 * i + 1]) - rowTimes(L.A, i, x, [i](int j) { return j < i; });
    const Eigen::Vector2d xi = L.inverse_diagonal[i] * s;
    x[2 * i] = xi.x();
    x[2 * i + 1] = xi.y();
  }
  // Residual, restricted.
  double* r = r_[l].data();
  multiply(L.A, x, r);
  for (int i = 0; i < 2 * n; ++i) r[i] = b[i] - r[i];
  double* bc = b_[l + 1].data();
  double* xc = x_[l + 1].data();
  const Csr& R = L.R;
  for (int c = 0; c < R.rows; ++c) {
    double u = 0, v = 0;
    for (int k = R.begin[c]; k < R.begin[c + 1]; ++k) {
      u += R.value[k] * r[2 * R.column[k]];
      v += R.value[k] * r[2 * R.column[k] + 1];
    }
    bc[2 * c] = u;
    bc[2 * c + 1] = v;
  }
  cycleFrom(l + 1, bc, xc);
  const Csr& P = *L.P;
  for (int i = 0; i < n; ++i)
    for (int k = P.begin[i]; k < P.begin[i + 1]; ++k) {
      x[2 * i] += P.value[k] * xc[2 * P.column[k]];
      x[2 * i + 1] += P.value[k] * xc[2 * P.column[k] + 1];
    }
  // Backward Gauss-Seidel: the cycle is symmetric.
  for (int i = n - 1; i >= 0; --i) {
    const Eigen::Vector2d s = Eigen::Vector2d(b[2 * i], b[2 * i + 1]) -
                              rowTimes(L.A, i, x, [i](int j) { return j != i; });
    const Eigen::Vector2d xi = L.inverse_diagonal[i] * s;
    x[2 * i] = xi.x();
    x[2 * i + 1] = xi.y();
  }
}

double BlockMultigrid::cycleWork() const {
  double work = 0;
  for (int l = 0; l + 1 < levelCount(); ++l) {
    // Two sweeps and the residual read every block (4 values), restriction and prolongation P.
    work +=
        (3.0 * 2 * levels_[l].A.blocks() + 4.0 * levels_[l].P->column.size()) * WorkCosts::kNonzero;
  }
  const double n = 2.0 * levels_.back().A.size;
  return work + n * n * WorkCosts::kNonzero;
}

double BlockMultigrid::setupWork() const {
  double work = 0;
  for (const Level& level : levels_) work += 8.0 * level.A.blocks() * WorkCosts::kNonzero;
  const double n = 2.0 * levels_.back().A.size;
  return work + n * n * n / 3 * WorkCosts::kFactorFlop;
}

bool CoupledMultigrid::update(const Eigen::SparseMatrix<double>& proxy,
                              const std::vector<double>& blocks) {
  const int n = static_cast<int>(proxy.rows());
  const bool first = static_cast<int>(scalar_.order().size()) != n || slot_entry_.empty();
  if (first) {
    // The first update: the stand-in's hierarchy (aggregates, prolongations, numbering), kept
    // for the later ones, whose new blocks only change the Galerkin products.
    if (!scalar_.build(proxy)) return false;
  }
  BlockCsr fresh;
  if (first) fresh = numberBlocks(proxy);
  BlockCsr& A = first ? fresh : blocks_.fine();
  for (size_t k = 0; k < slot_entry_.size(); ++k) {
    // The entry stored at (j, i) holds block (j, i); row i of the block matrix takes its
    // transpose.
    const double* b = &blocks[4 * k];
    double* out = &A.value[4 * static_cast<size_t>(slot_entry_[k])];
    const double scale = slot_scale_[k];
    out[0] = scale * b[0];
    out[1] = scale * b[2];
    out[2] = scale * b[1];
    out[3] = scale * b[3];
  }
  const bool built =
      first ? blocks_.build(scalar_.hierarchy(), std::move(fresh)) : blocks_.rebuild();
  spent_work_ += 6.0 * proxy.nonZeros() * WorkCosts::kNonzero;
  if (built) spent_work_ += blocks_.setupWork();
  return built;
}

BlockCsr CoupledMultigrid::numberBlocks(const Eigen::SparseMatrix<double>& proxy) {
  const std::vector<int>& order = scalar_.order();
  const std::vector<double>& root = scalar_.rootDiagonal();
  const int n = static_cast<int>(order.size());
  std::vector<int> new_of(n);
  for (int p = 0; p < n; ++p) new_of[order[p]] = p;
  // Row p of the block matrix is column order[p] of the symmetric pattern, scaled like the
  // stand-in's level 0.
  BlockCsr A;
  A.size = n;
  A.begin.assign(n + 1, 0);
  A.column.resize(proxy.nonZeros());
  A.value.resize(4 * static_cast<size_t>(proxy.nonZeros()));
  slot_entry_.assign(proxy.nonZeros(), 0);
  slot_scale_.assign(proxy.nonZeros(), 0.0);
  const int* outer = proxy.outerIndexPtr();
  const int* inner = proxy.innerIndexPtr();
  int entry = 0;
  for (int p = 0; p < n; ++p) {
    const int i = order[p];
    for (int k = outer[i]; k < outer[i + 1]; ++k, ++entry) {
      A.column[entry] = new_of[inner[k]];
      slot_entry_[k] = entry;
      slot_scale_[k] = 1 / (root[i] * root[inner[k]]);
    }
    A.begin[p + 1] = entry;
  }
  spent_work_ += 8.0 * proxy.nonZeros() * WorkCosts::kNonzero;
  return A;
}

void CoupledMultigrid::applyCycle(const double* r, double* z) const {
  scalar_.applyScaled(r, z, [&](const double* in, double* out) { blocks_.cycle(in, out); });
  spent_work_ += blocks_.cycleWork();
}

}  // namespace sdp
