// Building the patch (core/common/patch.h) from indexed triangles is the
// topology check of docs/method.md §1: one component, edge- and vertex-manifold, one boundary loop,
// χ = 1.
#pragma once

#include <Eigen/Core>

#include "core/common/patch.h"

namespace sdp {

struct PatchOptions {
  bool fill_holes = true;  // false: several boundary loops are an error
  int outer_vertex = -1;   // input index of a vertex on the outer loop; -1: the longest loop
};

// Builds the patch and checks it is a disk (after filling holes). Throws ParameterizationError
// naming the first problem found (index out of range, non-finite coordinate, repeated vertex in
// a face, duplicate face, non-manifold edge or vertex, inconsistent orientation, closed mesh,
// several components, several boundary loops when not filling, wrong Euler characteristic).
Patch buildPatch(const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& V,
                 const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& F,
                 const PatchOptions& options = {});

}  // namespace sdp
