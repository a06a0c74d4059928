// The one policy every linear system of the pipeline follows, and the direct factor they share.
//
// A system is solved by a sparse direct factorization up to a size (below it the factor is
// faster and exact), by an iterative method above it (where a factor's fill costs memory and
// time); an iterative solve that does not converge, or a hierarchy that cannot be built, moves
// the system to the direct factor for the rest of the run: a system the iteration could not
// converge on will not get easier with the next weights or right-hand side.
//
// Holders, one path each: the interior solve of eq. (1) (solve.h: multigrid BiCGSTAB, sparse
// LU), the as-rigid-as-possible global step (free_boundary.cpp: multigrid CG, LDLT) and the
// free-boundary Newton step (stretch_newton.cpp: coupled-multigrid CG, LDLT; its iterative path
// has no fallback, since the factor it would need is what did not fit). The crossovers are
// measured in docs/measurements.md.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/common/work.h"

namespace sdp {

// How a system is solved: by the path's size rule, or forced (tests and the solver bench).
enum class SolverMethod { Automatic, Direct, Multigrid };

// Unknowns (Newton: vertices) up to which each system is factored directly.
struct DirectUpTo {
  static constexpr int kInteriorSolve = 1000;  // LU against multigrid: crossover about 700
  static constexpr int kArapGlobalStep = 1000;
  static constexpr int kNewtonStep = 50000;  // vertices; 2 unknowns each
};

class SolvePath {
 public:
  SolvePath() = default;  // direct
  SolvePath(long long unknowns, int direct_up_to, SolverMethod method = SolverMethod::Automatic)
      : iterative_(method == SolverMethod::Multigrid ||
                   (method == SolverMethod::Automatic && unknowns > direct_up_to)) {}
  bool iterative() const { return iterative_; }
  // The iterative method failed: the direct factor from now on.
  void fallBack() {
    if (iterative_) fell_back_ = true;
    iterative_ = false;
  }
  bool fellBack() const { return fell_back_; }

 private:
  bool iterative_ = false;
  bool fell_back_ = false;
};

// A sparse LDLT factor of a symmetric matrix, its pattern analysed on the first factorization
// and kept for the later ones (the same pattern with new values), with the work (work.h) of each
// call counted from the factor's size.
class SymmetricFactor {
 public:
  bool factorize(const Eigen::SparseMatrix<double>& A) {
    if (!analyzed_) {
      ldlt_.analyzePattern(A);
      analyzed_ = true;
    }
    ldlt_.factorize(A);
    factored_ = ldlt_.info() == Eigen::Success;
    last_work_ = factored_ ? factorizationWork(ldlt_.matrixL().nestedExpression()) : 0;
    return factored_;
  }
  // The next factorize() analyses its matrix's pattern anew: for a matrix whose pattern changes
  // between calls (the grid Newton steps lay a new grid each time).
  void forgetPattern() { analyzed_ = false; }
  bool factored() const { return factored_; }
  // x = A^-1 b, column by column; false on a numerical failure or a non-finite result.
  template <class Rhs, class Solution>
  bool solve(const Rhs& b, Solution& x) {
    x = ldlt_.solve(b);
    last_work_ = b.cols() * substitutionWork(ldlt_.matrixL().nestedExpression());
    return ldlt_.info() == Eigen::Success && x.allFinite();
  }
  // Work of the last factorize() or solve().
  double lastWork() const { return last_work_; }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool analyzed_ = false;
  bool factored_ = false;
  double last_work_ = 0;
};

}  // namespace sdp
