// Disjoint sets (union-find) over indices 0..n-1, for grouping particles into connected bodies.
// A set's root is always its smallest index, so the grouping and the roots do not depend on the
// order the links are visited in (deterministic on any number of threads that produce the same
// links). Path halving keeps the trees flat.
#pragma once

#include <cstdint>
#include <numeric>
#include <vector>

namespace mf {

class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

  /// The smallest index of i's set.
  uint32_t root(uint32_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }

  /// Joins the sets of a and b.
  void unite(uint32_t a, uint32_t b) {
    a = root(a), b = root(b);
    if (a < b) parent_[b] = a;
    else if (b < a) parent_[a] = b;
  }

 private:
  std::vector<uint32_t> parent_;
};

}  // namespace mf
