// Smoothed-aggregation algebraic multigrid and a preconditioned BiCGSTAB for the interior system
// of eq. (1). The matrix is a non-symmetric M-matrix (unit diagonal, rows of -a_ij summing to at
// most 1) whose near-null space is the constant vector: the setting smoothed aggregation handles
// with mesh-independent convergence (8 iterations from 104k to 1.65M vertices), so the solve
// grows linearly with the vertex count. Greedy aggregates on the strong-connection graph, one
// damped Jacobi step on the prolongation, Galerkin coarse operators, Gauss-Seidel smoothing
// (forward before, backward after), W-cycles, dense LU at the bottom; docs/measurements.md has
// the numbers against sparse LU, UMFPACK and ILUT.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "csr.h"

namespace sdp {

struct MultigridSettings {
  double strength = 0.08;   // a_ij is strong when a_ij^2 > strength^2 a_ii a_jj (halved per level)
  int coarsest_size = 400;  // solved by dense LU at or below this many unknowns
  int coarsest_limit = 3000;  // larger when coarsening stalls: the hierarchy is not usable
  int max_levels = 16;
  // Coarse corrections per level: 2 = W-cycle (measured against V: docs/measurements.md).
  int cycle_index = 2;
  // Power iterations for the spectral radius in the prolongation damping (docs/measurements.md).
  int power_iterations = 6;
};

// Scratch vectors of the cycles; one per thread that applies the preconditioner.
struct MultigridWorkspace {
  std::vector<std::vector<double>> x, b, r, e;  // per coarse level
  Eigen::MatrixXd coarsest;                     // right-hand sides of the dense solve
};

class Multigrid {
 public:
  // Builds the hierarchy for `fine` (kept, and used as the level-0 operator).
  void build(SplitCsr fine, const MultigridSettings& settings = {});
  // New level-0 values on the same pattern (refinement reweighting): keeps the aggregates and
  // recomputes the prolongations and coarse operators. On three refinement steps at 414k
  // vertices a fully stale hierarchy needed 11, 13, 15 iterations, this 8, 7, 8 (a full rebuild
  // 7 each) while skipping a quarter of the setup.
  void rebuildWithSameAggregates(SplitCsr fine);

  bool empty() const { return levels_.empty(); }
  // False when coarsening stalled above coarsest_limit unknowns (e.g. no strong connections).
  bool usable() const {
    return !levels_.empty() && levels_.back().A.size <= settings_.coarsest_limit;
  }
  const SplitCsr& fine() const { return levels_.front().A; }
  int levelCount() const { return static_cast<int>(levels_.size()); }
  const SplitCsr& levelMatrix(int level) const { return levels_[level].A; }
  // Level `level`'s prolongation from level + 1 (rows: level's unknowns, columns: the coarser
  // level's); none on the last level.
  const Csr& prolongation(int level) const { return levels_[level].P; }
  double operatorComplexity() const;  // sum of nnz over all levels / nnz of level 0
  long long memoryBytes() const;
  // Work (work.h) of one cycle on u and v, of one BiCGSTAB iteration (two cycles, two products,
  // the vector updates), and of build() or rebuildWithSameAggregates(): from the hierarchy's
  // sizes alone.
  double cycleWork() const;
  double iterationWork() const;
  double setupWork(bool same_aggregates) const;

  // x = one cycle applied to b (from a zero start); K right-hand sides interleaved.
  template <int K>
  void cycle(const double* b, double* x, MultigridWorkspace& work) const;
  MultigridWorkspace makeWorkspace(int columns) const;

 private:
  struct Level {
    SplitCsr A;
    Csr P;                       // prolongation from the next coarser level (none on the last)
    std::vector<int> aggregate;  // coarse unknown of each unknown (-2: in none)
    int aggregates = 0;
  };
  SplitCsr coarsen(Level& level) const;  // sets level.P, returns the coarser operator
  void factorCoarsest();
  template <int K>
  void cycleFrom(int level, const double* b, double* x, MultigridWorkspace& work) const;

  MultigridSettings settings_;
  std::vector<Level> levels_;
  Eigen::PartialPivLU<Eigen::MatrixXd> coarsest_lu_;
};

}  // namespace sdp
