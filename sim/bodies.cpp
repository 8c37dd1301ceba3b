#include "bodies.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "disjoint_sets.h"
#include "neighbor_search.h"

namespace mf {

namespace {

Real roundnessOf(const Vec3* x, const std::vector<uint32_t>& members, const Vec3& centroid) {
  if (members.size() < 4) return 1;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (uint32_t i : members) {
    const Vec3 d = x[i] - centroid;
    const Eigen::Vector3d e(d.x, d.y, d.z);
    cov += e * e.transpose();
  }
  const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
  return lambda(2) > 0 ? std::sqrt(std::max(0.0, lambda(0)) / lambda(2)) : 1;
}

}  // namespace

FluidBodies findBodies(const Vec3* x, const int32_t* phase, size_t n, Real linkDistance) {
  FluidBodies out;
  out.bodyOf.assign(n, -1);
  if (n == 0) return out;
  Vec3 lo = x[0];
  for (size_t i = 1; i < n; ++i)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], x[i][a]);
  CellGrid grid;
  grid.build(x, n, lo - Vec3(linkDistance, linkDistance, linkDistance), linkDistance);
  NeighborLists near;
  grid.findNeighbors(grid, linkDistance, true, near);
  DisjointSets sets(n);
  for (size_t i = 0; i < n; ++i)
    for (uint64_t k = near.begin(i), e = near.end(i); k < e; ++k) {
      const uint32_t j = near.indices[k];
      if (phase[j] == phase[i]) sets.unite(uint32_t(i), j);
    }
  // Members in ascending index order, grouped by root (the smallest member).
  std::vector<int32_t> groupOfRoot(n, -1);
  std::vector<FluidBody> bodies;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t r = sets.root(uint32_t(i));
    if (groupOfRoot[r] < 0) {
      groupOfRoot[r] = int32_t(bodies.size());
      bodies.emplace_back();
      bodies.back().phase = phase[i];
      bodies.back().lower = bodies.back().upper = x[i];
    }
    FluidBody& b = bodies[size_t(groupOfRoot[r])];
    b.members.push_back(uint32_t(i));
    b.centroid += x[i];
    for (int a = 0; a < 3; ++a) b.lower[a] = std::min(b.lower[a], x[i][a]), b.upper[a] = std::max(b.upper[a], x[i][a]);
  }
  for (FluidBody& b : bodies) {
    b.centroid = b.centroid * (1 / Real(b.size()));
    b.roundness = roundnessOf(x, b.members, b.centroid);
  }
  // Bodies were created in order of their smallest member, which breaks ties below.
  std::stable_sort(bodies.begin(), bodies.end(), [](const FluidBody& a, const FluidBody& b) {
    if (a.phase != b.phase) return a.phase < b.phase;
    return a.size() > b.size();
  });
  for (size_t k = 0; k < bodies.size(); ++k)
    for (uint32_t i : bodies[k].members) out.bodyOf[i] = int32_t(k);
  out.bodies = std::move(bodies);
  return out;
}

}  // namespace mf
