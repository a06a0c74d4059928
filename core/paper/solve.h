// Eq. (1): sum_j a_ij (U_j - U_i) = 0 for interior vertices, boundary vertices fixed.
// Interior unknowns only. Large systems: BiCGSTAB preconditioned by smoothed-aggregation
// multigrid (multigrid.h), u and v at once, the hierarchy kept across calls; small systems, and
// any iterative solve that does not converge tightly, use the sparse LU factorization. Why
// multigrid (against SparseLU, UMFPACK, ILUT-BiCGSTAB, measured by bench/solver_bench):
// docs/measurements.md.
//
// Numbering: patch vertices (patch.h) in, patch vertices out; inside, interior unknowns in
// breadth-first order (unknown_ / interior_vertex_). Matrix: #interior x #interior, u and v
// solved together as two interleaved right-hand sides.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <memory>
#include <vector>

#include "boundary.h"
#include "core/common/patch.h"
#include "core/linear/multigrid.h"
#include "core/linear/solve_path.h"

namespace sdp {

struct SolverSettings {
  SolverMethod method = SolverMethod::Automatic;
  // Automatic: LU up to this many unknowns (linear/solve_path.h).
  int direct_up_to = DirectUpTo::kInteriorSolve;
  // Relative residual ||b - A x|| / ||b|| of u and of v (docs/measurements.md). The pipeline
  // checks every map for flipped faces anyway; a map that fails the check is solved again to
  // tight_tolerance (tighten()) before any other fallback, so a loose solve never costs a fold,
  // only a few more iterations on the rare mesh that needs them.
  double tolerance = 1e-8;
  double tight_tolerance = 1e-12;
  int max_iterations = 100;  // BiCGSTAB iterations before falling back to LU (it takes 7-11)
  // u and v on two threads instead of in lockstep on one (lockstep reads the matrix once for
  // both; docs/measurements.md has why it is off).
  bool parallel_columns = false;
  MultigridSettings multigrid;
};

// What the last solve() did (for benchmarks and tests; not part of the user report).
struct SolverStats {
  bool multigrid = false;         // the iterative path ran
  bool fell_back = false;         // ... and did not converge, so LU solved the system
  bool reused_hierarchy = false;  // the multigrid aggregates came from an earlier call
  int iterations = 0;             // BiCGSTAB iterations (the larger of u and v)
  double relative_residual = 0;   // worst of u and v, after the solve
  int levels = 0;
  double operator_complexity = 0;
  long long hierarchy_bytes = 0;
  double setup_seconds = 0;  // assembly + hierarchy (or LU factorization)
  double solve_seconds = 0;  // iterations (or LU back-substitution)
  // Work of the solve (work.h): assembly, setup and iterations (or the LU factorization),
  // counted from sizes and iteration counts, so the same on every run.
  double work = 0;
};

class InteriorSolver {
 public:
  explicit InteriorSolver(const Patch& patch, const SolverSettings& settings = {});
  // Row weights parallel to patch.ring_vertex (rows sum to 1), boundary polygon parallel to
  // patch.boundary_loop. Reuses the symbolic analysis / multigrid hierarchy across calls
  // (refinement iterations), and the previous solution as the starting guess.
  LocalUVs solve(const std::vector<double>& weights, const Polygon& boundary);
  const SolverStats& lastStats() const { return stats_; }
  // Later solves go to settings.tight_tolerance. Returns false when that changes nothing (the
  // last solve was direct, or already tight).
  bool tighten();
  // Later solves go to `tolerance` when it is looser than the current one and no solve has
  // been tightened: for a map that is only a start. A fold still leads to tighten().
  void loosen(double tolerance);

 private:
  using RightHandSides = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
  void assemble(const std::vector<double>& weights, const LocalUVs& uv, SplitCsr& A,
                RightHandSides& rhs) const;
  bool solveIteratively(SplitCsr A, const RightHandSides& rhs, RightHandSides& x);
  void solveDirectly(const SplitCsr& A, const RightHandSides& rhs, RightHandSides& x);

  const Patch& patch_;
  SolverSettings settings_;
  SolverStats stats_;
  std::vector<int> unknown_;          // patch vertex -> interior unknown index, -1 on the boundary
  std::vector<int> interior_vertex_;  // interior unknown index -> patch vertex
  int unknowns_ = 0;
  bool analyzed_ = false;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
  SolvePath path_;  // multigrid or LU, and the fall back from one to the other
  Multigrid multigrid_;
  RightHandSides previous_;  // last iterative solution: the next call's starting guess
};

}  // namespace sdp
