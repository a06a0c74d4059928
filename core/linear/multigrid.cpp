#include "multigrid.h"

#include <algorithm>
#include <cmath>

#include "core/common/parallel.h"
#include "core/common/work.h"

namespace sdp {
namespace {

// Symmetric graph of strong connections: an edge when a_ij or a_ji is strong, so aggregates do
// not depend on which side of a non-symmetric pair is looked at.
struct Graph {
  std::vector<int> begin, adjacent;
  int degree(int i) const { return begin[i + 1] - begin[i]; }
};

Graph strongGraph(const SplitCsr& A, double theta) {
  const int n = A.size;
  const double theta2 = theta * theta;
  auto strong = [&](int i, int j, double v) {
    return v * v > theta2 * std::abs(A.diagonal[i] * A.diagonal[j]);
  };
  Graph g;
  g.begin.assign(n + 1, 0);
  for (int i = 0; i < n; ++i)
    A.forEachOffDiagonal(i, [&](int j, double v) {
      if (strong(i, j, v)) {
        ++g.begin[i + 1];
        ++g.begin[j + 1];
      }
    });
  for (int i = 0; i < n; ++i) g.begin[i + 1] += g.begin[i];
  g.adjacent.resize(g.begin[n]);
  std::vector<int> fill(g.begin.begin(), g.begin.end() - 1);
  for (int i = 0; i < n; ++i)
    A.forEachOffDiagonal(i, [&](int j, double v) {
      if (strong(i, j, v)) {
        g.adjacent[fill[i]++] = j;
        g.adjacent[fill[j]++] = i;
      }
    });
  // A pair strong both ways was added twice: keep it once (compaction in place).
  std::vector<int> seen(n, -1);
  int out = 0, row_start = 0;
  for (int i = 0; i < n; ++i) {
    const int row_end = g.begin[i + 1];
    g.begin[i] = out;
    for (int k = row_start; k < row_end; ++k) {
      const int j = g.adjacent[k];
      if (seen[j] == i) continue;
      seen[j] = i;
      g.adjacent[out++] = j;
    }
    row_start = row_end;
  }
  g.begin[n] = out;
  g.adjacent.resize(out);
  return g;
}

constexpr int kUnassigned = -1;
constexpr int kIsolated = -2;  // no strong neighbour: the smoother alone resolves it

// Vanek-Mandel-Brezina greedy aggregation: roots whose whole strong neighbourhood is free take
// it; leftovers join a neighbouring aggregate; what remains forms new aggregates. Roots are
// tried along the front of the aggregates made so far (nodes three steps from the last root
// first): in input order, a mesh whose vertices come in subdivision levels packs its roots
// loosely and gets aggregates twice too large (16 vs 13 BiCGSTAB iterations on the face mesh).
std::vector<int> aggregate(const Graph& g, int n, int& aggregates) {
  std::vector<int> agg(n, kUnassigned);
  for (int i = 0; i < n; ++i)
    if (g.degree(i) == 0) agg[i] = kIsolated;
  aggregates = 0;
  std::vector<int> front, stamp(n, -1);
  size_t front_next = 0;
  int scan = 0;
  while (true) {
    int i = -1;
    while (front_next < front.size() && i < 0) {
      const int candidate = front[front_next++];
      if (agg[candidate] == kUnassigned) i = candidate;
    }
    if (i < 0) {
      front.clear();
      front_next = 0;
      while (scan < n && agg[scan] != kUnassigned) ++scan;
      if (scan == n) break;
      i = scan++;
    }
    bool free = true;
    for (int k = g.begin[i]; k < g.begin[i + 1] && free; ++k)
      free = agg[g.adjacent[k]] == kUnassigned;
    if (!free) continue;
    agg[i] = aggregates;
    for (int k = g.begin[i]; k < g.begin[i + 1]; ++k) agg[g.adjacent[k]] = aggregates;
    for (int k = g.begin[i]; k < g.begin[i + 1]; ++k) {
      const int j = g.adjacent[k];
      for (int m = g.begin[j]; m < g.begin[j + 1]; ++m) {
        const int q = g.adjacent[m];
        if (agg[q] != kUnassigned) continue;
        for (int o = g.begin[q]; o < g.begin[q + 1]; ++o) {
          const int t = g.adjacent[o];
          if (agg[t] == kUnassigned && stamp[t] != aggregates) {
            stamp[t] = aggregates;
            front.push_back(t);
          }
        }
      }
    }
    ++aggregates;
  }
  const std::vector<int> roots = agg;
  for (int i = 0; i < n; ++i) {
    if (agg[i] != kUnassigned) continue;
    for (int k = g.begin[i]; k < g.begin[i + 1]; ++k)
      if (roots[g.adjacent[k]] >= 0) {
        agg[i] = roots[g.adjacent[k]];
        break;
      }
  }
  for (int i = 0; i < n; ++i) {
    if (agg[i] != kUnassigned) continue;
    agg[i] = aggregates;
    for (int k = g.begin[i]; k < g.begin[i + 1]; ++k)
      if (agg[g.adjacent[k]] == kUnassigned) agg[g.adjacent[k]] = aggregates;
    ++aggregates;
  }
  return agg;
}

// Spectral radius of D^-1 A by power iteration from a fixed oscillating start (the top of the
// spectrum is the oscillatory modes). It approaches from below; the damping 4/3 / rho that uses
// it has a wide flat optimum (omega 0.75..1.0 gave the same iteration counts on the face mesh).
double spectralRadiusEstimate(const SplitCsr& A, int iterations) {
  std::vector<double> x(A.size), y(A.size);
  unsigned state = 12345u;
  for (double& v : x) {
    state = state * 1664525u + 1013904223u;
    v = (state >> 31) ? 1.0 : -1.0;
  }
  double rho = 1.0;
  for (int it = 0; it < iterations; ++it) {
    multiply<1>(A, x.data(), y.data());
    double xx = 0, yy = 0;
    for (int i = 0; i < A.size; ++i) {
      y[i] /= A.diagonal[i];
      xx += x[i] * x[i];
      yy += y[i] * y[i];
    }
    if (!(yy > 0)) break;
    rho = std::sqrt(yy / xx);
    const double scale = 1.0 / std::sqrt(yy);
    for (int i = 0; i < A.size; ++i) x[i] = y[i] * scale;
  }
  return rho;
}

// P = (I - omega D^-1 A) P_tent, P_tent the 0/1 aggregate indicator (the constant vector is the
// near-null space: interior rows of A sum to zero). All of A smooths, not only its strong part:
// lumping the weak entries onto the diagonal cost 13 instead of 10 iterations on the face mesh.
Csr smoothedProlongation(const SplitCsr& A, const std::vector<int>& agg, int aggregates,
                         double omega) {
  Csr P;
  P.rows = A.size;
  P.cols = aggregates;
  P.begin.assign(A.size + 1, 0);
  P.column.reserve(A.size * 3);
  P.value.reserve(A.size * 3);
  std::vector<int> slot(aggregates, -1);
  for (int i = 0; i < A.size; ++i) {
    const int row_start = static_cast<int>(P.column.size());
    auto add = [&](int c, double v) {
      if (c < 0) return;
      if (slot[c] < row_start) {
        slot[c] = static_cast<int>(P.column.size());
        P.column.push_back(c);
        P.value.push_back(v);
      } else {
        P.value[slot[c]] += v;
      }
    };
    add(agg[i], 1.0 - omega);
    const double scale = -omega / A.diagonal[i];
    A.forEachOffDiagonal(i, [&](int j, double v) { add(agg[j], scale * v); });
    P.begin[i + 1] = static_cast<int>(P.column.size());
  }
  return P;
}

}  // namespace

Csr transposed(const Csr& M) {
  Csr T;
  T.rows = M.cols;
  T.cols = M.rows;
  T.begin.assign(M.cols + 1, 0);
  for (int c : M.column) ++T.begin[c + 1];
  for (int c = 0; c < M.cols; ++c) T.begin[c + 1] += T.begin[c];
  T.column.resize(M.column.size());
  T.value.resize(M.value.size());
  std::vector<int> fill(T.begin.begin(), T.begin.end() - 1);
  for (int i = 0; i < M.rows; ++i)
    for (int k = M.begin[i]; k < M.begin[i + 1]; ++k) {
      const int at = fill[M.column[k]]++;
      T.column[at] = i;
      T.value[at] = M.value[k];
    }
  return T;
}

namespace {

// A_c = R A P with R = P^T, row by row of R without forming A P (which would be the largest
// temporary of the setup). Coarse rows are split into one contiguous chunk per thread.
SplitCsr galerkin(const SplitCsr& A, const Csr& P) {
  const Csr R = transposed(P);
  const int nc = R.rows;
  std::vector<Csr> chunk(parallelWorkers());
  parallelFor(nc, 2048, [&](int first, int last, int worker) {
    Csr& out = chunk[worker];
    out.begin.push_back(0);
    // Two dense accumulators with lists of their touched columns: first the fine row
    // w = sum_i R_ci A_i, then A_c row c = w P. Summing w first takes 36 instead of 55
    // accumulations per fine row. Raw pointers, so the compiler need not reload vector bases
    // that a push_back could move.
    std::vector<double> fine_acc_storage(A.size, 0.0), acc_storage(nc, 0.0);
    std::vector<int> fine_mark_storage(A.size, -1), fine_touched_storage(A.size);
    std::vector<int> mark_storage(nc, -1), touched_storage(nc);
    double* __restrict fine_acc = fine_acc_storage.data();
    int* __restrict fine_mark = fine_mark_storage.data();
    int* __restrict fine_touched = fine_touched_storage.data();
    double* __restrict acc = acc_storage.data();
    int* __restrict mark = mark_storage.data();
    int* __restrict touched = touched_storage.data();
    const int* __restrict p_begin = P.begin.data();
    const int* __restrict p_column = P.column.data();
    const double* __restrict p_value = P.value.data();
    for (int c = first; c < last; ++c) {
      int fine_count = 0, count = 0;
      auto addFine = [&](int j, double v) {
        if (fine_mark[j] != c) {
          fine_mark[j] = c;
          fine_touched[fine_count++] = j;
          fine_acc[j] = v;
        } else {
          fine_acc[j] += v;
        }
      };
      for (int k = R.begin[c]; k < R.begin[c + 1]; ++k) {
        const int i = R.column[k];
        const double r = R.value[k];
        addFine(i, r * A.diagonal[i]);
        A.forEachOffDiagonal(i, [&](int j, double v) { addFine(j, r * v); });
      }
      for (int f = 0; f < fine_count; ++f) {
        const int j = fine_touched[f];
        const double w = fine_acc[j];
        for (int k = p_begin[j]; k < p_begin[j + 1]; ++k) {
          const int col = p_column[k];
          if (mark[col] != c) {
            mark[col] = c;
            touched[count++] = col;
            acc[col] = w * p_value[k];
          } else {
            acc[col] += w * p_value[k];
          }
        }
      }
      for (int k = 0; k < count; ++k) {
        out.column.push_back(touched[k]);
        out.value.push_back(acc[touched[k]]);
      }
      out.begin.push_back(static_cast<int>(out.column.size()));
    }
  });
  SplitCsr Ac;
  Ac.startRows(nc, 0.0);
  int row = 0;
  for (const Csr& part : chunk)
    for (size_t r = 0; r + 1 < part.begin.size(); ++r, ++row) {
      for (int k = part.begin[r]; k < part.begin[r + 1]; ++k)
        Ac.add(row, part.column[k], part.value[k]);
      Ac.endRow(row);
    }
  return Ac;
}

// K interleaved columns of one row (u and v: one SSE2 register).
template <int K>
using Block = Eigen::Array<double, K, 1>;

template <int K>
inline Block<K> load(const double* p) {
  return Eigen::Map<const Block<K>>(p);
}

template <int K>
inline void store(double* p, const Block<K>& v) {
  Eigen::Map<Block<K>> target(p);
  target = v;
}

// Row i of M times the K columns of x.
template <int K>
inline Block<K> rowTimes(const CsrRows& M, int i, const double* __restrict x) {
  const int* __restrict column = M.column.data();
  const double* __restrict value = M.value.data();
  Block<K> s = Block<K>::Zero();
  for (int k = M.begin[i]; k < M.begin[i + 1]; ++k) s += value[k] * load<K>(x + column[k] * K);
  return s;
}

// First forward Gauss-Seidel sweep from x = 0: only the lower part is non-zero on the right.
template <int K>
void gaussSeidelFromZero(const SplitCsr& A, const double* __restrict b, double* __restrict x) {
  for (int i = 0; i < A.size; ++i)
    store<K>(x + i * K, (load<K>(b + i * K) - rowTimes<K>(A.lower, i, x)) / A.diagonal[i]);
}

template <int K>
void gaussSeidelBackward(const SplitCsr& A, const double* __restrict b, double* __restrict x) {
  for (int i = A.size - 1; i >= 0; --i)
    store<K>(x + i * K,
             (load<K>(b + i * K) - rowTimes<K>(A.lower, i, x) - rowTimes<K>(A.upper, i, x)) /
                 A.diagonal[i]);
}

// bc = P^T r with r = b - A x right after gaussSeidelFromZero, where (D + L) x = b, so
// r = -U x: the residual needs only the upper part.
template <int K>
void restrictUpperResidual(const SplitCsr& A, const Csr& P, const double* __restrict x,
                           double* __restrict bc) {
  std::fill(bc, bc + static_cast<size_t>(P.cols) * K, 0.0);
  for (int i = 0; i < A.size; ++i) {
    const Block<K> r = -rowTimes<K>(A.upper, i, x);
    for (int k = P.begin[i]; k < P.begin[i + 1]; ++k) {
      double* target = bc + P.column[k] * K;
      store<K>(target, load<K>(target) + P.value[k] * r);
    }
  }
}

template <int K>
void prolongAdd(const Csr& P, const double* __restrict xc, double* __restrict x) {
  for (int i = 0; i < P.rows; ++i) store<K>(x + i * K, load<K>(x + i * K) + rowTimes<K>(P, i, xc));
}

}  // namespace

template <int K>
void multiply(const SplitCsr& A, const double* __restrict x, double* __restrict y) {
  for (int i = 0; i < A.size; ++i)
    store<K>(y + i * K, A.diagonal[i] * load<K>(x + i * K) + rowTimes<K>(A.lower, i, x) +
                            rowTimes<K>(A.upper, i, x));
}

void Multigrid::build(SplitCsr fine, const MultigridSettings& settings) {
  settings_ = settings;
  levels_.clear();
  levels_.push_back(Level{std::move(fine), Csr{}, {}});
  double theta = settings.strength;
  while (static_cast<int>(levels_.size()) < settings.max_levels &&
         levels_.back().A.size > settings.coarsest_size) {
    Level& level = levels_.back();
    int aggregates = 0;
    std::vector<int> agg = aggregate(strongGraph(level.A, theta), level.A.size, aggregates);
    if (aggregates == 0 || aggregates >= level.A.size) break;  // no coarsening possible
    level.aggregate = std::move(agg);
    level.aggregates = aggregates;
    levels_.push_back(Level{coarsen(level), Csr{}, {}});
    theta *= 0.5;
  }
  factorCoarsest();
}

void Multigrid::rebuildWithSameAggregates(SplitCsr fine) {
  levels_.front().A = std::move(fine);
  for (size_t l = 0; l + 1 < levels_.size(); ++l) levels_[l + 1].A = coarsen(levels_[l]);
  factorCoarsest();
}

SplitCsr Multigrid::coarsen(Level& level) const {
  const double omega = (4.0 / 3.0) / spectralRadiusEstimate(level.A, settings_.power_iterations);
  level.P = smoothedProlongation(level.A, level.aggregate, level.aggregates, omega);
  return galerkin(level.A, level.P);
}

void Multigrid::factorCoarsest() {
  const SplitCsr& last = levels_.back().A;
  if (last.size > settings_.coarsest_limit) {
    coarsest_lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>();
    return;  // coarsening stalled: not usable (a dense factor would not fit)
  }
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(last.size, last.size);
  for (int i = 0; i < last.size; ++i) {
    dense(i, i) = last.diagonal[i];
    last.forEachOffDiagonal(i, [&](int j, double v) { dense(i, j) = v; });
  }
  coarsest_lu_.compute(dense);
}

double Multigrid::operatorComplexity() const {
  double total = 0;
  for (const Level& l : levels_) total += static_cast<double>(l.A.nonZeros());
  return total / static_cast<double>(levels_.front().A.nonZeros());
}

double Multigrid::cycleWork() const {
  // Visits per level as cycleFrom makes them: cycle_index per visit of the level above, but the
  // coarsest level once per visit of its parent (no W-cycle repeat above it).
  const int levels = levelCount();
  double visits = 1, work = 0;
  for (int l = 0; l < levels; ++l) {
    const Level& level = levels_[l];
    if (l + 1 == levels) {  // dense LU back-substitution
      const double n = level.A.size;
      work += visits * n * n * WorkCosts::kNonzero;
      break;
    }
    // Two Gauss-Seidel sweeps, the residual, restriction and prolongation, and on W-cycles the
    // coarse level's residual products.
    const double coarse_repeats = l + 2 < levels ? settings_.cycle_index - 1 : 0;
    work += visits * WorkCosts::kNonzero *
            (2.0 * level.A.nonZeros() + 2.0 * level.P.column.size() +
             coarse_repeats * levels_[l + 1].A.nonZeros());
    if (l + 2 < levels) visits *= settings_.cycle_index;
  }
  return work;
}

double Multigrid::iterationWork() const {
  return 2 * cycleWork() + 2.0 * fine().nonZeros() * WorkCosts::kNonzero +
         12.0 * fine().size * WorkCosts::kVectorEntry;
}

double Multigrid::setupWork(bool same_aggregates) const {
  double nonzeros = 0;
  for (const Level& l : levels_) nonzeros += static_cast<double>(l.A.nonZeros());
  const double coarsest = levels_.empty() ? 0 : levels_.back().A.size;
  return nonzeros * (same_aggregates ? WorkCosts::kRebuildNonzero : WorkCosts::kSetupNonzero) +
         coarsest * coarsest * coarsest / 3 * WorkCosts::kFactorFlop;
}

long long Multigrid::memoryBytes() const {
  long long bytes = 0;
  for (const Level& l : levels_) {
    for (const CsrRows* m : {&l.A.lower, &l.A.upper, static_cast<const CsrRows*>(&l.P)})
      bytes += 4LL * (m->begin.size() + m->column.size()) + 8LL * m->value.size();
    bytes += 8LL * l.A.diagonal.size() + 4LL * l.aggregate.size();
  }
  return bytes + 8LL * coarsest_lu_.rows() * coarsest_lu_.rows();
}

MultigridWorkspace Multigrid::makeWorkspace(int columns) const {
  MultigridWorkspace work;
  const size_t levels = levels_.size();
  work.x.resize(levels);
  work.b.resize(levels);
  work.r.resize(levels);
  work.e.resize(levels);
  for (size_t l = 1; l < levels; ++l) {
    const size_t n = static_cast<size_t>(levels_[l].A.size) * columns;
    work.x[l].assign(n, 0.0);
    work.b[l].assign(n, 0.0);
    if (settings_.cycle_index > 1 && l + 1 < levels) {
      work.r[l].assign(n, 0.0);
      work.e[l].assign(n, 0.0);
    }
  }
  work.coarsest.resize(levels_.back().A.size, columns);
  return work;
}

template <int K>
void Multigrid::cycleFrom(int level, const double* b, double* x, MultigridWorkspace& work) const {
  const Level& L = levels_[level];
  const int n = L.A.size;
  if (level + 1 == static_cast<int>(levels_.size())) {
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < K; ++c) work.coarsest(i, c) = b[i * K + c];
    work.coarsest = coarsest_lu_.solve(work.coarsest);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < K; ++c) x[i * K + c] = work.coarsest(i, c);
    return;
  }
  double* bc = work.b[level + 1].data();
  double* xc = work.x[level + 1].data();
  gaussSeidelFromZero<K>(L.A, b, x);
  restrictUpperResidual<K>(L.A, L.P, x, bc);
  cycleFrom<K>(level + 1, bc, xc, work);
  if (level + 2 < static_cast<int>(levels_.size())) {
    // W-cycle: further coarse corrections from the coarse residual.
    const SplitCsr& Ac = levels_[level + 1].A;
    const size_t nc = static_cast<size_t>(Ac.size) * K;
    double* rc = work.r[level + 1].data();
    double* ec = work.e[level + 1].data();
    for (int g = 1; g < settings_.cycle_index; ++g) {
      multiply<K>(Ac, xc, rc);
      for (size_t i = 0; i < nc; ++i) rc[i] = bc[i] - rc[i];
      cycleFrom<K>(level + 1, rc, ec, work);
      for (size_t i = 0; i < nc; ++i) xc[i] += ec[i];
    }
  }
  prolongAdd<K>(L.P, xc, x);
  gaussSeidelBackward<K>(L.A, b, x);
}

template <int K>
void Multigrid::cycle(const double* b, double* x, MultigridWorkspace& work) const {
  cycleFrom<K>(0, b, x, work);
}

// y = A x with the column dots (y, w) and (y, y) taken on the way: the Krylov vector updates
// are memory-bound passes, and each fused dot saves one.
template <int K>
void multiplyWithDots(const SplitCsr& A, const double* __restrict x, double* __restrict y,
                      const double* __restrict w, double* yw, double* yy) {
  Block<K> sw = Block<K>::Zero(), sy = Block<K>::Zero();
  for (int i = 0; i < A.size; ++i) {
    const Block<K> row = A.diagonal[i] * load<K>(x + i * K) + rowTimes<K>(A.lower, i, x) +
                         rowTimes<K>(A.upper, i, x);
    store<K>(y + i * K, row);
    sw += row * load<K>(w + i * K);
    sy += row * row;
  }
  for (int c = 0; c < K; ++c) {
    yw[c] = sw(c);
    yy[c] = sy(c);
  }
}

template void Multigrid::cycle<1>(const double*, double*, MultigridWorkspace&) const;
template void Multigrid::cycle<2>(const double*, double*, MultigridWorkspace&) const;
template void multiply<1>(const SplitCsr&, const double*, double*);
template void multiply<2>(const SplitCsr&, const double*, double*);
template void multiplyWithDots<1>(const SplitCsr&, const double*, double*, const double*, double*,
                                  double*);
template void multiplyWithDots<2>(const SplitCsr&, const double*, double*, const double*, double*,
                                  double*);

}  // namespace sdp
