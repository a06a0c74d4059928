// Work, counted instead of time (docs/method.md §4): the refinement budget is a multiple of the
// linear map's work, and work is computed from the sizes of what a step touches (matrix
// nonzeros, faces, ring entries) and the iterations it ran, never read off a clock. The same mesh
// and options then get the same refinement steps, so the same UVs, on any machine and under any
// load, with any number of threads.
//
// One unit is about one nanosecond of one core of the 2-core machine the constants were fitted
// on (bench/determinism.py sets each stage's units against its measured seconds, in
// bench/results/determinism.md). Only ratios matter for the default budget (a multiple of the
// linear map's work); the absolute size matters only for kMinRefineWork.
#pragma once

#include <cstdint>

namespace sdp {

struct WorkCosts {
  // Sparse kernels, per stored nonzero visited (u and v together, as the solvers run them).
  static constexpr double kNonzero = 2.0;
  // Vector updates per entry (u and v) in a Krylov iteration.
  static constexpr double kVectorEntry = 1.0;
  // Multigrid setup (strength graph, aggregates, smoothed prolongation, Galerkin products) per
  // nonzero of the whole hierarchy; a rebuild on the same aggregates skips about a quarter.
  static constexpr double kSetupNonzero = 40.0;
  static constexpr double kRebuildNonzero = 30.0;
  // Per face: stretchMetrics, a flip count, the ARAP local step, the Newton energy and the
  // Newton per-face Hessian (update).
  static constexpr double kMetricsFace = 60.0;
  static constexpr double kFlipCheckFace = 8.0;
  static constexpr double kArapLocalFace = 60.0;
  static constexpr double kEnergyFace = 25.0;
  static constexpr double kNewtonHessianFace = 80.0;
  // Per face or vertex of the patch for the stages before the solve (topology and frames).
  static constexpr double kTopologyFace = 120.0;
  // Per ring entry: the weights of one neighbour (straightest weights walk two planes).
  static constexpr double kWeightEntry = 120.0;
  // Sparse direct factorizations: per floating-point multiply-add of the factorization.
  static constexpr double kFactorFlop = 0.5;
};

// The least refinement work of a default run: small and medium patches are refined until the
// steps stop gaining (1.5-2 s here), large ones get a multiple of their linear map's work. At
// 1.75e9 the 26k-vertex face.off stops at L2 1.3256 in 1.6 s (2e9: 1.3240, 1.8-2.1 s); every
// other shared patch converges below it (camelhead at 1.67e9; 1.5e9 would cost it 2 %).
constexpr double kMinRefineWork = 1.75e9;

// Work spent so far, in units.
struct WorkMeter {
  double spent = 0;
};

// Work of a sparse factorization from its column-major factor L (an Eigen sparse matrix, e.g.
// SimplicialLDLT's matrixL().nestedExpression()): the sum over columns of (column count)^2
// multiply-adds, and two visits of every entry for the back-substitution.
template <class ColumnMajorFactor>
double factorizationWork(const ColumnMajorFactor& L) {
  double flops = 0;
  for (long long c = 0; c < L.outerSize(); ++c) {
    const double count = L.outerIndexPtr()[c + 1] - L.outerIndexPtr()[c];
    flops += count * count;
  }
  return flops * WorkCosts::kFactorFlop;
}
template <class ColumnMajorFactor>
double substitutionWork(const ColumnMajorFactor& L) {
  return 2.0 * static_cast<double>(L.nonZeros()) * WorkCosts::kNonzero;
}

}  // namespace sdp
