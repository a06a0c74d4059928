// Eq. (1): sum_j a_ij (U_j - U_i) = 0 for interior vertices, boundary vertices fixed.
// Interior unknowns only; the matrix is factored once and solved for u and v together.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <memory>
#include <vector>

#include "boundary.h"
#include "patch.h"

namespace sdp {

using LocalUVs = std::vector<Eigen::Vector2d>;  // one per patch vertex

class InteriorSolver {
 public:
  explicit InteriorSolver(const Patch& patch);
  // Row weights parallel to patch.ring_vertex (rows sum to 1), boundary polygon parallel to
  // patch.boundary_loop. Reuses the symbolic analysis across calls (refinement iterations).
  LocalUVs solve(const std::vector<double>& weights, const Polygon& boundary);

 private:
  const Patch& patch_;
  std::vector<int> unknown_;  // patch vertex -> interior unknown index, -1 on the boundary
  int unknowns_ = 0;
  bool analyzed_ = false;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
};

}  // namespace sdp
