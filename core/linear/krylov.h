// Krylov solvers, the one home of the loops every solve here runs:
//   solveBiCgStab<K>  right-preconditioned BiCGSTAB on K interleaved right-hand sides of a
//                     Multigrid's fine operator (the interior solve: not symmetric), the
//                     multigrid cycle as preconditioner;
//   solveConjugateGradients<K>  the same for a symmetric positive-definite operator (the
//                     free-boundary Laplacian);
//   truncatedConjugateGradients  preconditioned CG for a symmetric positive-definite operator
//                     given as callables (the matrix-free Newton steps).
// Vectors: interleaved K columns, x[i * K + c] is row i of column c.
#pragma once

#include <Eigen/Core>
#include <algorithm>

#include "multigrid.h"

namespace sdp {

struct KrylovOutcome {
  int iterations = 0;
  double relative_residual = 0;  // ||b - A x|| / ||b||, worst column, recomputed at the end
  bool converged = false;
};

// Each column has its own scalars and stops moving when it converges; the run restarts from
// the true residual when the recurrence claims convergence too early, and stops at a breakdown
// or a restart that gains nothing. x holds the initial guess and the result.
template <int K>
KrylovOutcome solveBiCgStab(const Multigrid& mg, const double* b, double* x, double tolerance,
                            int max_iterations);

// Preconditioned conjugate gradients on K interleaved right-hand sides of a Multigrid's fine
// operator, which must be symmetric positive definite (the free-boundary Laplacian), with the
// cycle (symmetric: Gauss-Seidel forward before, backward after) as preconditioner. x holds the
// initial guess and the result. One cycle and one product per iteration, BiCGSTAB's half.
template <int K>
KrylovOutcome solveConjugateGradients(const Multigrid& mg, const double* b, double* x,
                                      double tolerance, int max_iterations);

// Truncated preconditioned conjugate gradients for A d = rhs from d = 0, to the relative
// residual `tolerance` or `max_iterations`: every iterate of an A-descent is a descent direction,
// so a loose solve still gives a usable step. The Polak-Ribiere beta (clamped at 0) tolerates a
// preconditioner that is not exactly symmetric. It stops early where A shows no positive
// curvature. apply(p, q) sets q = A p; precondition(r, z) sets z ~ A^-1 r. Returns the iterations.
template <class Apply, class Precondition>
int truncatedConjugateGradients(const Apply& apply, const Precondition& precondition,
                                const Eigen::VectorXd& rhs, Eigen::VectorXd& direction,
                                double tolerance, int max_iterations) {
  const Eigen::Index size = rhs.size();
  direction.setZero(size);
  Eigen::VectorXd r = rhs, z(size), z_old(size), p(size), q(size);
  const double stop = tolerance * r.norm();
  precondition(r, z);
  p = z;
  double rz = r.dot(z);
  int it = 0;
  while (it < max_iterations && r.norm() > stop) {
    ++it;
    apply(p, q);
    const double curvature = p.dot(q);
    if (!(curvature > 0) || !(rz > 0)) break;
    const double alpha = rz / curvature;
    direction += alpha * p;
    r -= alpha * q;
    z_old.swap(z);
    precondition(r, z);
    const double rz_new = r.dot(z);
    const double beta = std::max(0.0, (rz_new - r.dot(z_old)) / rz);
    rz = rz_new;
    p = z + beta * p;
  }
  return it;
}

}  // namespace sdp
