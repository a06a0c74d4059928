// Smoothed-aggregation algebraic multigrid and a preconditioned BiCGSTAB for the interior system
// of eq. (1). The matrix is a non-symmetric M-matrix (unit diagonal, rows of -a_ij summing to at
// most 1) whose near-null space is the constant vector, the setting smoothed aggregation handles
// with mesh-independent convergence, so the solve grows linearly with the vertex count.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

namespace sdp {

// Square sparse matrix: rows in CSR form for the off-diagonal entries, the diagonal apart (the
// smoother and every product here need it separately).
struct SplitCsr {
  int size = 0;
  std::vector<int> begin;        // size + 1 row starts into column/value
  std::vector<int> column;       // off-diagonal columns
  std::vector<double> value;     // off-diagonal values
  std::vector<double> diagonal;  // size

  long long nonZeros() const { return static_cast<long long>(column.size()) + size; }
};

// Rectangular sparse matrix in CSR form (prolongation and restriction).
struct Csr {
  int rows = 0, cols = 0;
  std::vector<int> begin;
  std::vector<int> column;
  std::vector<double> value;
};

struct MultigridSettings {
  double strength = 0.08;   // a_ij is strong when a_ij^2 > strength^2 a_ii a_jj (halved per level)
  int coarsest_size = 400;  // solved by dense LU at or below this many unknowns
  int max_levels = 16;
};

// Scratch vectors of one V-cycle; one per thread that applies the preconditioner.
struct MultigridWorkspace {
  std::vector<std::vector<double>> x, b;  // per coarse level
  Eigen::MatrixXd coarsest;               // right-hand sides of the dense solve
};

class Multigrid {
 public:
  // Builds the hierarchy for `fine` (kept, and used as the level-0 operator).
  void build(SplitCsr fine, const MultigridSettings& settings = {});
  // Replaces the level-0 values (same pattern) without rebuilding the coarse levels: the
  // coarse correction goes stale but stays a good preconditioner for nearby weights.
  void replaceFineValues(const SplitCsr& fine);

  bool empty() const { return levels_.empty(); }
  const SplitCsr& fine() const { return levels_.front().A; }
  int levelCount() const { return static_cast<int>(levels_.size()); }
  double operatorComplexity() const;  // sum of nnz over all levels / nnz of level 0
  long long memoryBytes() const;

  // x = one V(1,1)-cycle applied to b (x starts from zero); K right-hand sides interleaved.
  template <int K>
  void vcycle(const double* b, double* x, MultigridWorkspace& work) const;
  MultigridWorkspace makeWorkspace(int columns) const;

 private:
  struct Level {
    SplitCsr A;
    Csr P;  // prolongation to this level from the next coarser one (empty on the last level)
  };
  template <int K>
  void cycleFrom(int level, const double* b, double* x, MultigridWorkspace& work) const;

  std::vector<Level> levels_;
  Eigen::PartialPivLU<Eigen::MatrixXd> coarsest_lu_;
};

struct KrylovOutcome {
  int iterations = 0;
  double relative_residual = 0;  // ||b - A x|| / ||b||, worst column, recomputed at the end
  bool converged = false;
};

// Right-preconditioned BiCGSTAB on K interleaved right-hand sides in lockstep (each column has
// its own scalars and stops when it converges). x holds the initial guess and the result.
template <int K>
KrylovOutcome solveBiCgStab(const Multigrid& mg, const double* b, double* x, double tolerance,
                            int max_iterations);

// y = A x on K interleaved columns.
template <int K>
void multiply(const SplitCsr& A, const double* x, double* y);

}  // namespace sdp
