// 1-to-4 midpoint subdivision, used to grow the shared meshes for the scaling benchmark.
#pragma once

#include <unordered_map>

#include "core/parameterize.h"

namespace sdp::bench {

inline void subdivideMidpoint(Positions& V, Triangles& F) {
  std::unordered_map<long long, int> midpoint;
  midpoint.reserve(F.rows() * 2);
  std::vector<Eigen::RowVector3d> added;
  const int n = static_cast<int>(V.rows());
  auto mid = [&](int a, int b) {
    const long long key = static_cast<long long>(std::min(a, b)) * (1LL << 32) + std::max(a, b);
    auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    const int index = n + static_cast<int>(added.size());
    added.push_back(0.5 * (V.row(a) + V.row(b)));
    midpoint.emplace(key, index);
    return index;
  };
  Triangles G(F.rows() * 4, 3);
  for (int f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    G.row(4 * f) << a, ab, ca;
    G.row(4 * f + 1) << ab, b, bc;
    G.row(4 * f + 2) << ca, bc, c;
    G.row(4 * f + 3) << ab, bc, ca;
  }
  Positions W(n + added.size(), 3);
  W.topRows(n) = V;
  for (size_t k = 0; k < added.size(); ++k) W.row(n + k) = added[k];
  V.swap(W);
  F.swap(G);
}

}  // namespace sdp::bench
