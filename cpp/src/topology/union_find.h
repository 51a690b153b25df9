#pragma once
// Disjoint sets over 0..n-1 (private to the topology chapter's sources).
#include <numeric>
#include <vector>

namespace meshsmith::topology {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];  // path halving
    return x;
  }

  /// Joins the sets of a and b; the smaller root becomes the representative (deterministic).
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return;
    if (a < b) parent_[b] = a;
    else parent_[a] = b;
  }

 private:
  std::vector<int> parent_;
};

}  // namespace meshsmith::topology
