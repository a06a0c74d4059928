// Breadth-first (Cuthill-McKee without the degree sort) numbering of a graph's nodes, the one
// order every solver here puts its unknowns in: nodes that are neighbours in the mesh are near in
// memory, so every sweep reads x from cache (in input order a subdivided mesh puts a vertex and
// its neighbours megabytes apart).
#pragma once

#include <vector>

namespace sdp {

// The eligible nodes of 0..n-1 in breadth-first order: first the front grown from
// `first_front` (in its order), then a new front from each eligible node not yet reached, in
// index order. `for_each_neighbour(v, visit)` calls visit(w) for each neighbour w of v.
template <class Eligible, class ForEachNeighbour>
std::vector<int> breadthFirstOrder(int n, const std::vector<int>& first_front, Eligible eligible,
                                   ForEachNeighbour for_each_neighbour) {
  std::vector<int> order;
  order.reserve(static_cast<size_t>(n));
  std::vector<bool> placed(static_cast<size_t>(n), false);
  auto visit = [&](int v) {
    if (placed[v] || !eligible(v)) return;
    placed[v] = true;
    order.push_back(v);
  };
  auto grow = [&](size_t head) {
    for (; head < order.size(); ++head) for_each_neighbour(order[head], visit);
  };
  for (int v : first_front) visit(v);
  grow(0);
  for (int seed = 0; seed < n; ++seed) {
    const size_t head = order.size();
    visit(seed);
    grow(head);
  }
  return order;
}

}  // namespace sdp
