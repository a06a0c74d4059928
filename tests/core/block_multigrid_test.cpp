// The coupled multigrid (core/linear/block_multigrid.h) on a system whose u and v are coupled:
// a grid Laplacian L with a 2x2 coupling block C per entry, H = L (x) C plus a small shift, the
// shape of the Newton system. Its cycle is symmetric (conjugate gradients need that) and, as a
// preconditioner, converges where the scalar stand-in's cycle, which drops the coupling, lags.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <vector>

#include "core/linear/block_multigrid.h"

namespace sdp {
namespace {

struct CoupledSystem {
  Eigen::SparseMatrix<double> L;  // the stand-in (n x n)
  std::vector<double> blocks;     // H's blocks per nonzero of L, in its storage order
  Eigen::Matrix2d C;
};

CoupledSystem gridSystem(int n, double coupling) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j) { return j * n + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double diagonal = 1e-3;
      for (auto [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int a = i + di, b = j + dj;
        if (a < 0 || b < 0 || a >= n || b >= n) continue;
        t.emplace_back(id(i, j), id(a, b), -1.0);
        diagonal += 1;
      }
      t.emplace_back(id(i, j), id(i, j), diagonal);
    }
  CoupledSystem s;
  s.L.resize(n * n, n * n);
  s.L.setFromTriplets(t.begin(), t.end());
  s.L.makeCompressed();
  s.C << 1, coupling, coupling, 1;
  s.blocks.resize(4 * s.L.nonZeros());
  for (int k = 0; k < s.L.nonZeros(); ++k) {
    const double a = s.L.valuePtr()[k];
    s.blocks[4 * k] = a * s.C(0, 0);
    s.blocks[4 * k + 1] = a * s.C(0, 1);
    s.blocks[4 * k + 2] = a * s.C(1, 0);
    s.blocks[4 * k + 3] = a * s.C(1, 1);
  }
  return s;
}

Eigen::VectorXd times(const CoupledSystem& s, const Eigen::VectorXd& x) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  for (int c = 0; c < s.L.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.L, c); it; ++it)
      y.segment<2>(2 * it.row()) += it.value() * s.C * x.segment<2>(2 * c);
  return y;
}

// Preconditioned conjugate gradients to a relative residual of 1e-8; the iterations taken.
template <class Cycle>
int pcgIterations(const CoupledSystem& s, const Eigen::VectorXd& b, Cycle&& cycle) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), r = b, z(b.size()), p, q;
  cycle(r.data(), z.data());
  p = z;
  double rz = r.dot(z);
  for (int it = 1; it <= 200; ++it) {
    q = times(s, p);
    const double alpha = rz / p.dot(q);
    x += alpha * p;
    r -= alpha * q;
    if (r.norm() < 1e-8 * b.norm()) return it;
    cycle(r.data(), z.data());
    const double rz_new = r.dot(z);
    p = z + (rz_new / rz) * p;
    rz = rz_new;
  }
  return 201;
}

TEST(CoupledMultigrid, CycleIsSymmetric) {
  const CoupledSystem s = gridSystem(40, 0.9);
  CoupledMultigrid mg;
  ASSERT_TRUE(mg.update(s.L, s.blocks));
  const Eigen::VectorXd x = Eigen::VectorXd::Random(2 * s.L.rows()),
                        y = Eigen::VectorXd::Random(2 * s.L.rows());
  Eigen::VectorXd cx(x.size()), cy(y.size());
  mg.applyCycle(x.data(), cx.data());
  mg.applyCycle(y.data(), cy.data());
  EXPECT_NEAR(cx.dot(y), x.dot(cy), 1e-9 * std::abs(cx.dot(y)));
  EXPECT_GT(cx.dot(x), 0);
}

TEST(CoupledMultigrid, KeepsTheCouplingTheScalarCycleDrops) {
  const CoupledSystem s = gridSystem(80, 0.95);  // u and v nearly tied: C's eigenvalues 1.95, 0.05
  CoupledMultigrid coupled;
  ASSERT_TRUE(coupled.update(s.L, s.blocks));
  LaplacianMultigrid scalar;
  ASSERT_TRUE(scalar.build(s.L));
  const Eigen::VectorXd b = Eigen::VectorXd::Random(2 * s.L.rows());
  const int with_coupling =
      pcgIterations(s, b, [&](const double* r, double* z) { coupled.applyCycle(r, z); });
  const int without =
      pcgIterations(s, b, [&](const double* r, double* z) { scalar.applyCycle(r, z); });
  EXPECT_LE(with_coupling, 15);
  EXPECT_LT(2 * with_coupling, without) << with_coupling << " against " << without;
  // New values on the same pattern (a later Newton step): rebuilt in place, as good.
  CoupledSystem weaker = gridSystem(80, 0.5);
  ASSERT_TRUE(coupled.update(weaker.L, weaker.blocks));
  EXPECT_LE(pcgIterations(weaker, b, [&](const double* r, double* z) { coupled.applyCycle(r, z); }),
            15);
}

}  // namespace
}  // namespace sdp
