#include "solve.h"

#include <string>

#include "error.h"

namespace sdp {

InteriorSolver::InteriorSolver(const Patch& patch)
    : patch_(patch), unknown_(patch.vertexCount(), -1) {
  for (int v = 0; v < patch.vertexCount(); ++v)
    if (!patch.on_boundary[v]) unknown_[v] = unknowns_++;
}

LocalUVs InteriorSolver::solve(const std::vector<double>& weights, const Polygon& boundary) {
  const Patch& p = patch_;
  LocalUVs uv(p.vertexCount(), Eigen::Vector2d::Zero());
  for (size_t k = 0; k < p.boundary_loop.size(); ++k) uv[p.boundary_loop[k]] = boundary[k];
  if (unknowns_ == 0) return uv;

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(p.ring_vertex.size() + unknowns_);
  Eigen::Matrix<double, Eigen::Dynamic, 2> rhs =
      Eigen::Matrix<double, Eigen::Dynamic, 2>::Zero(unknowns_, 2);
  for (int v = 0; v < p.vertexCount(); ++v) {
    const int row = unknown_[v];
    if (row < 0) continue;
    entries.emplace_back(row, row, 1.0);
    for (int k = p.ring_begin[v]; k < p.ring_begin[v + 1]; ++k) {
      const int j = p.ring_vertex[k];
      if (unknown_[j] >= 0)
        entries.emplace_back(row, unknown_[j], -weights[k]);
      else
        rhs.row(row) += weights[k] * uv[j].transpose();
    }
  }
  Eigen::SparseMatrix<double> A(unknowns_, unknowns_);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  if (!analyzed_) {
    lu_.analyzePattern(A);
    analyzed_ = true;
  }
  lu_.factorize(A);
  if (lu_.info() != Eigen::Success)
    throw ParameterizationError("the linear system could not be factored: " +
                                lu_.lastErrorMessage());
  const Eigen::Matrix<double, Eigen::Dynamic, 2> x = lu_.solve(rhs);
  if (lu_.info() != Eigen::Success || !x.allFinite())
    throw ParameterizationError("the linear solve failed (non-finite result)");
  for (int v = 0; v < p.vertexCount(); ++v)
    if (unknown_[v] >= 0) uv[v] = x.row(unknown_[v]).transpose();
  return uv;
}

}  // namespace sdp
