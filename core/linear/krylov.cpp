#include "krylov.h"

#include <cmath>
#include <vector>

namespace sdp {
namespace {

// The norms of the K interleaved columns of v[0 .. size).
template <int K>
void columnNorms(const double* v, size_t size, double* norm) {
  double s[K] = {};
  const size_t n = size / K;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < K; ++c) s[c] += v[i * K + c] * v[i * K + c];
  for (int c = 0; c < K; ++c) norm[c] = std::sqrt(s[c]);
}

template <int K>
void columnDots(const std::vector<double>& a, const std::vector<double>& b, double* dot) {
  double s[K] = {};
  const size_t n = a.size() / K;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < K; ++c) s[c] += a[i * K + c] * b[i * K + c];
  for (int c = 0; c < K; ++c) dot[c] = s[c];
}

// r = b - A x and its column norms; returns the worst relative residual ||r|| / ||b||.
template <int K>
double trueResidual(const SplitCsr& A, const double* b, const double* x, std::vector<double>& r,
                    const double* bnorm, double* rnorm) {
  multiply<K>(A, x, r.data());
  for (size_t i = 0; i < r.size(); ++i) r[i] = b[i] - r[i];
  columnNorms<K>(r.data(), r.size(), rnorm);
  double worst = 0;
  for (int c = 0; c < K; ++c) worst = std::max(worst, bnorm[c] > 0 ? rnorm[c] / bnorm[c] : 0.0);
  return worst;
}

template <int K>
bool anyOf(const bool (&flags)[K]) {
  for (int c = 0; c < K; ++c)
    if (flags[c]) return true;
  return false;
}

// BiCGSTAB's state for one run; each step below is a stage of the classic iteration, with the
// column scalars kept apart (a finished column keeps its x and r).
template <int K>
class BiCgStab {
 public:
  BiCgStab(const Multigrid& mg, const double* b, double* x, double tolerance, int max_iterations)
      : mg_(mg),
        A_(mg.fine()),
        N_(static_cast<size_t>(A_.size) * K),
        b_(b),
        x_(x),
        tolerance_(tolerance),
        max_iterations_(max_iterations),
        r_(N_),
        rhat_(N_),
        p_(N_, 0.0),
        v_(N_, 0.0),
        hat_(N_),
        t_(N_),
        work_(mg.makeWorkspace(K)) {
    columnNorms<K>(b, N_, bnorm_);
  }

  KrylovOutcome run() {
    KrylovOutcome out;
    out.relative_residual = trueResidual();
    while (out.relative_residual > tolerance_ && out.iterations < max_iterations_) {
      restart();
      bool breakdown = false;
      while (out.iterations < max_iterations_ && !breakdown && anyActive()) {
        ++out.iterations;
        breakdown = !searchDirection() || !firstHalf() || !stabilize() || !secondHalf();
      }
      const double before = out.relative_residual;
      out.relative_residual = trueResidual();
      if (breakdown || !std::isfinite(out.relative_residual)) break;
      if (!(out.relative_residual < before)) break;  // a restart that gains nothing will not
    }
    out.converged = std::isfinite(out.relative_residual) && out.relative_residual <= tolerance_;
    return out;
  }

 private:
  double trueResidual() { return sdp::trueResidual<K>(A_, b_, x_, r_, bnorm_, rnorm_); }

  void restart() {
    for (int c = 0; c < K; ++c) {
      active_[c] = rnorm_[c] > tolerance_ * bnorm_[c];
      rho_[c] = alpha_[c] = omega_[c] = 1.0;
    }
    rhat_ = r_;
    std::fill(p_.begin(), p_.end(), 0.0);
    std::fill(v_.begin(), v_.end(), 0.0);
    columnDots<K>(rhat_, r_, rho_new_);  // later taken in the update of r
  }

  bool anyActive() const { return anyOf<K>(active_); }

  // p = r + beta (p - omega v), hat = M p, v = A hat, alpha = rho / (rhat, v).
  bool searchDirection() {
    bool breakdown = false;
    double beta[K];
    for (int c = 0; c < K; ++c) {
      beta[c] = 0;
      if (!active_[c]) continue;
      if (!(std::abs(rho_new_[c]) > 0) || !std::isfinite(rho_new_[c])) {
        breakdown = true;
        continue;
      }
      beta[c] = (rho_new_[c] / rho_[c]) * (alpha_[c] / omega_[c]);
      rho_[c] = rho_new_[c];
    }
    if (breakdown) return false;
    for (size_t i = 0; i < N_; i += K)
      for (int c = 0; c < K; ++c)
        p_[i + c] = r_[i + c] + beta[c] * (p_[i + c] - omega_[c] * v_[i + c]);
    mg_.template cycle<K>(p_.data(), hat_.data(), work_);
    double rv[K], vv[K];
    multiplyWithDots<K>(A_, hat_.data(), v_.data(), rhat_.data(), rv, vv);
    for (int c = 0; c < K; ++c) {
      alpha_[c] = 0;
      if (!active_[c]) continue;
      if (!(std::abs(rv[c]) > 0) || !std::isfinite(rv[c])) {
        breakdown = true;
        continue;
      }
      alpha_[c] = rho_[c] / rv[c];
    }
    return !breakdown;
  }

  // x += alpha hat, r -= alpha v (r now holds s); a column whose s is small enough is done.
  bool firstHalf() {
    double snorm[K] = {};
    for (size_t i = 0; i < N_; i += K)
      for (int c = 0; c < K; ++c) {
        x_[i + c] += alpha_[c] * hat_[i + c];
        r_[i + c] -= alpha_[c] * v_[i + c];
        snorm[c] += r_[i + c] * r_[i + c];
      }
    for (int c = 0; c < K; ++c) {
      second_half_[c] = active_[c] && std::sqrt(snorm[c]) > tolerance_ * bnorm_[c];
      if (!second_half_[c]) active_[c] = false;
    }
    return true;
  }

  // hat = M s, t = A hat, omega = (t, s) / (t, t).
  bool stabilize() {
    bool breakdown = false;
    mg_.template cycle<K>(r_.data(), hat_.data(), work_);
    double ts[K], tt[K];
    multiplyWithDots<K>(A_, hat_.data(), t_.data(), r_.data(), ts, tt);
    for (int c = 0; c < K; ++c) {
      if (!second_half_[c]) {
        omega_[c] = 1.0;  // keeps the next beta finite; the column no longer moves
        continue;
      }
      if (!(tt[c] > 0) || !std::isfinite(ts[c])) {
        breakdown = true;
        continue;
      }
      omega_[c] = ts[c] / tt[c];
      if (!(std::abs(omega_[c]) > 0)) breakdown = true;
    }
    return !breakdown;
  }

  // x += omega hat, r -= omega t, with the new rho = (rhat, r) and the residual norms.
  bool secondHalf() {
    bool breakdown = false;
    double r2[K] = {};
    for (int c = 0; c < K; ++c) {
      rho_new_[c] = 0;
      if (!second_half_[c]) omega_[c] = 0;  // x and r of a finished column stay as they are
    }
    for (size_t i = 0; i < N_; i += K)
      for (int c = 0; c < K; ++c) {
        x_[i + c] += omega_[c] * hat_[i + c];
        r_[i + c] -= omega_[c] * t_[i + c];
        r2[c] += r_[i + c] * r_[i + c];
        rho_new_[c] += rhat_[i + c] * r_[i + c];
      }
    for (int c = 0; c < K; ++c)
      if (!second_half_[c]) omega_[c] = 1.0;  // keeps the next beta finite
    for (int c = 0; c < K; ++c) {
      if (!second_half_[c]) continue;
      rnorm_[c] = std::sqrt(r2[c]);
      if (!std::isfinite(rnorm_[c])) breakdown = true;
      active_[c] = rnorm_[c] > tolerance_ * bnorm_[c];
    }
    return !breakdown;
  }

  const Multigrid& mg_;
  const SplitCsr& A_;
  const size_t N_;
  const double* b_;
  double* x_;
  const double tolerance_;
  const int max_iterations_;
  // hat holds M p, then M s (x takes the first as soon as alpha is known).
  std::vector<double> r_, rhat_, p_, v_, hat_, t_;
  MultigridWorkspace work_;
  double bnorm_[K], rnorm_[K];
  bool active_[K], second_half_[K];
  double rho_[K], alpha_[K], omega_[K], rho_new_[K];
};

// Preconditioned conjugate gradients on K columns at once, each with its own scalars; a column
// stops moving once its residual meets the tolerance (or shows no positive curvature).
template <int K>
class ConjugateGradients {
 public:
  ConjugateGradients(const Multigrid& mg, const double* b, double* x, double tolerance)
      : mg_(mg),
        A_(mg.fine()),
        N_(static_cast<size_t>(A_.size) * K),
        b_(b),
        x_(x),
        tolerance_(tolerance),
        r_(N_),
        z_(N_),
        p_(N_),
        q_(N_),
        work_(mg.makeWorkspace(K)) {
    columnNorms<K>(b, N_, bnorm_);
  }

  KrylovOutcome run(int max_iterations) {
    KrylovOutcome out;
    out.relative_residual = trueResidual();
    for (int c = 0; c < K; ++c) active_[c] = rnorm_[c] > tolerance_ * bnorm_[c];
    if (anyActive()) {
      mg_.cycle<K>(r_.data(), z_.data(), work_);
      p_ = z_;
      columnDots<K>(r_, z_, rz_);
    }
    while (out.iterations < max_iterations && anyActive()) {
      ++out.iterations;
      step();
    }
    out.relative_residual = trueResidual();
    out.converged = std::isfinite(out.relative_residual) && out.relative_residual <= tolerance_;
    return out;
  }

 private:
  void step() {
    multiply<K>(A_, p_.data(), q_.data());
    double pq[K], alpha[K];
    columnDots<K>(p_, q_, pq);
    for (int c = 0; c < K; ++c) {
      if (active_[c] && !(pq[c] > 0 && rz_[c] > 0)) active_[c] = false;
      alpha[c] = active_[c] ? rz_[c] / pq[c] : 0.0;
    }
    for (size_t i = 0; i < N_; i += K)
      for (int c = 0; c < K; ++c) {
        x_[i + c] += alpha[c] * p_[i + c];
        r_[i + c] -= alpha[c] * q_[i + c];
      }
    columnNorms<K>(r_.data(), N_, rnorm_);
    for (int c = 0; c < K; ++c)
      if (!(rnorm_[c] > tolerance_ * bnorm_[c])) active_[c] = false;
    if (!anyActive()) return;
    mg_.cycle<K>(r_.data(), z_.data(), work_);
    double rz_new[K], beta[K];
    columnDots<K>(r_, z_, rz_new);
    for (int c = 0; c < K; ++c) {
      beta[c] = active_[c] ? rz_new[c] / rz_[c] : 0.0;
      rz_[c] = rz_new[c];
    }
    for (size_t i = 0; i < N_; i += K)
      for (int c = 0; c < K; ++c)
        if (active_[c]) p_[i + c] = z_[i + c] + beta[c] * p_[i + c];
  }
  double trueResidual() { return sdp::trueResidual<K>(A_, b_, x_, r_, bnorm_, rnorm_); }
  bool anyActive() const { return anyOf<K>(active_); }

  const Multigrid& mg_;
  const SplitCsr& A_;
  const size_t N_;
  const double* b_;
  double* x_;
  const double tolerance_;
  std::vector<double> r_, z_, p_, q_;
  MultigridWorkspace work_;
  double bnorm_[K], rnorm_[K], rz_[K] = {};
  bool active_[K] = {};
};

}  // namespace

template <int K>
KrylovOutcome solveConjugateGradients(const Multigrid& mg, const double* b, double* x,
                                      double tolerance, int max_iterations) {
  return ConjugateGradients<K>(mg, b, x, tolerance).run(max_iterations);
}
template KrylovOutcome solveConjugateGradients<2>(const Multigrid&, const double*, double*, double,
                                                  int);

template <int K>
KrylovOutcome solveBiCgStab(const Multigrid& mg, const double* b, double* x, double tolerance,
                            int max_iterations) {
  return BiCgStab<K>(mg, b, x, tolerance, max_iterations).run();
}

template KrylovOutcome solveBiCgStab<1>(const Multigrid&, const double*, double*, double, int);
template KrylovOutcome solveBiCgStab<2>(const Multigrid&, const double*, double*, double, int);

}  // namespace sdp
