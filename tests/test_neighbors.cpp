// Neighbour search against brute force, on clustered random points and across two grids.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sim/neighbor_search.h"

namespace {

std::vector<mf::Vec3> randomPoints(size_t n, uint32_t seed, double extent) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, extent);
  std::vector<mf::Vec3> p(n);
  for (auto& x : p) x = {u(rng), u(rng) * 0.5, u(rng)};
  // A few exact duplicates and points on cell boundaries: the cases that break searches.
  p[1] = p[0];
  p[2] = {0.1, 0.1, 0.1};
  p[3] = {0.1 + 0.05, 0.1, 0.1};
  return p;
}

void expectMatchesBruteForce(const std::vector<mf::Vec3>& a, const std::vector<mf::Vec3>& b, double radius,
                             bool excludeSelf, const mf::NeighborLists& nl) {
  ASSERT_EQ(nl.rows(), a.size());
  size_t total = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    std::vector<uint32_t> expected;
    for (size_t j = 0; j < b.size(); ++j) {
      if (excludeSelf && i == j) continue;
      if (mf::lengthSquared(a[i] - b[j]) < radius * radius) expected.push_back(uint32_t(j));
    }
    std::vector<uint32_t> got(nl.indices.begin() + nl.begin(i), nl.indices.begin() + nl.end(i));
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected) << "row " << i;
    total += got.size();
  }
  EXPECT_GT(total, a.size());  // the test is not vacuous
}

TEST(NeighborSearch, SelfQueryMatchesBruteForce) {
  const auto p = randomPoints(3000, 1, 0.5);
  const double h = 0.05;
  mf::CellGrid g;
  g.build(p.data(), p.size(), {-0.1, -0.1, -0.1}, h);
  mf::NeighborLists nl;
  g.findNeighbors(g, h, true, nl);
  expectMatchesBruteForce(p, p, h, true, nl);
}

TEST(NeighborSearch, CrossQueryAndSmallerRadius) {
  const auto a = randomPoints(1500, 2, 0.5), b = randomPoints(2500, 3, 0.5);
  const double h = 0.05;
  mf::CellGrid ga, gb;
  ga.build(a.data(), a.size(), {-0.1, -0.1, -0.1}, h);
  gb.build(b.data(), b.size(), {-0.1, -0.1, -0.1}, h);
  mf::NeighborLists nl;
  ga.findNeighbors(gb, h, false, nl);
  expectMatchesBruteForce(a, b, h, false, nl);
  ga.findNeighbors(gb, 0.6 * h, false, nl);
  expectMatchesBruteForce(a, b, 0.6 * h, false, nl);
}

// A compact grid looks its cells up in a dense table, a sparse one (clusters far apart) by binary
// search over the Morton keys: both must give the same lists in the same order, since the
// simulation's sums follow that order.
TEST(NeighborSearch, SparseAndDenseCellLookupsGiveTheSameLists) {
  const double h = 0.05;
  const auto near = randomPoints(2000, 5, 0.5);
  auto far = near;
  for (int k = 0; k < 50; ++k) far.push_back(mf::Vec3(200.0 + 0.01 * k, 100.0, 150.0));  // 4000 x 2000 x 3000 cells apart
  mf::CellGrid compact, sparse;
  compact.build(near.data(), near.size(), {-0.1, -0.1, -0.1}, h);
  sparse.build(far.data(), far.size(), {-0.1, -0.1, -0.1}, h);
  mf::NeighborLists a, b;
  compact.findNeighbors(compact, h, true, a);
  sparse.findNeighbors(sparse, h, true, b);
  expectMatchesBruteForce(far, far, h, true, b);
  for (size_t i = 0; i < near.size(); ++i)
    ASSERT_TRUE(std::equal(a.indices.begin() + a.begin(i), a.indices.begin() + a.end(i), b.indices.begin() + b.begin(i),
                           b.indices.begin() + b.end(i)))
        << "row " << i;
}

TEST(NeighborSearch, SortedOrderFollowsZOrderOfCells) {
  const auto p = randomPoints(2000, 4, 0.5);
  const double h = 0.05;
  const mf::Vec3 origin(-0.1, -0.1, -0.1);
  mf::CellGrid g;
  g.build(p.data(), p.size(), origin, h);
  uint64_t prevKey = 0;
  uint32_t prevIndex = 0;
  for (size_t k = 0; k < g.sortedIndices().size(); ++k) {
    const uint32_t i = g.sortedIndices()[k];
    int32_t c[3];
    g.cellOf(p[i], c);
    const uint64_t key = mf::mortonKey(c[0], c[1], c[2]);
    if (k > 0) {
      ASSERT_TRUE(key > prevKey || (key == prevKey && i > prevIndex)) << "position " << k;
    }
    prevKey = key;
    prevIndex = i;
  }
  EXPECT_EQ(mf::mortonKey(1, 0, 0), 1u);
  EXPECT_EQ(mf::mortonKey(0, 1, 0), 2u);
  EXPECT_EQ(mf::mortonKey(0, 0, 1), 4u);
  EXPECT_EQ(mf::mortonKey(2, 0, 0), 8u);
}

}  // namespace
