// Union-find over 0..n-1, each set named by its smallest member (so numbering by first member
// is the same on every run): faces joined into pieces (connectivity, atlas charts by UVs).
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace sdp {

class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace sdp
