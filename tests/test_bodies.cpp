// Bodies of fluid (sim/bodies.h): what issue 23's scene measures count. Checked on lattice
// shapes whose answer is known by construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "sim/bodies.h"

namespace {

using mf::Real;
using mf::Vec3;

constexpr Real kSpacing = 0.01;

// A lattice ball of radius r spacings around c.
void addBall(std::vector<Vec3>& x, std::vector<int32_t>& phase, Vec3 c, int r, int32_t p) {
  for (int i = -r; i <= r; ++i)
    for (int j = -r; j <= r; ++j)
      for (int k = -r; k <= r; ++k)
        if (i * i + j * j + k * k <= r * r) {
          x.push_back(c + Vec3(i, j, k) * kSpacing);
          phase.push_back(p);
        }
}

std::vector<size_t> sizes(const mf::FluidBodies& b) {
  std::vector<size_t> s;
  for (const auto& body : b.bodies) s.push_back(body.size());
  return s;
}

TEST(Bodies, BallsApartAreTwoBodiesAndBallsWithinTheLinkAreOne) {
  std::vector<Vec3> x;
  std::vector<int32_t> phase;
  addBall(x, phase, Vec3(0, 0, 0), 3, 0);  // 123 particles
  const size_t first = x.size();
  // The first ball reaches x = 0.03: 2 spacings apart, not linked at 1.5.
  addBall(x, phase, Vec3(0.07, 0, 0), 2, 0);  // 33 particles, x from 0.05
  auto b = mf::findBodies(x.data(), phase.data(), x.size(), 1.5 * kSpacing);
  ASSERT_EQ(b.bodies.size(), 2u);
  EXPECT_EQ(sizes(b), (std::vector<size_t>{first, x.size() - first}));  // largest first
  for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(b.bodyOf[i], i < first ? 0 : 1);
  // One spacing closer: the nearest particles are 1 spacing apart, so the balls are one body.
  for (size_t i = first; i < x.size(); ++i) x[i].x -= kSpacing;
  b = mf::findBodies(x.data(), phase.data(), x.size(), 1.5 * kSpacing);
  EXPECT_EQ(b.bodies.size(), 1u);
}

TEST(Bodies, FluidsAreNotLinkedToEachOther) {
  std::vector<Vec3> x;
  std::vector<int32_t> phase;
  addBall(x, phase, Vec3(0, 0, 0), 3, 0);
  // A bubble of phase 1 inside: its lattice interleaves with the water's at half a spacing.
  addBall(x, phase, Vec3(0.005, 0.005, 0.005), 1, 1);
  const auto b = mf::findBodies(x.data(), phase.data(), x.size(), 1.5 * kSpacing);
  ASSERT_EQ(b.bodies.size(), 2u);
  EXPECT_EQ(b.bodies[0].phase, 0);
  EXPECT_EQ(b.bodies[1].phase, 1);
  EXPECT_EQ(b.bodies[1].size(), 7u);
  EXPECT_NEAR(b.bodies[1].centroid.x, 0.005, 1e-12);
}

TEST(Bodies, RoundnessTellsABallFromASheet) {
  std::vector<Vec3> x;
  std::vector<int32_t> phase;
  addBall(x, phase, Vec3(0, 0, 0), 4, 0);
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 12; ++k) x.push_back(Vec3(0.5 + i * kSpacing, 0.5, 0.5 + k * kSpacing)), phase.push_back(0);
  const auto b = mf::findBodies(x.data(), phase.data(), x.size(), 1.5 * kSpacing);
  ASSERT_EQ(b.bodies.size(), 2u);
  // The lattice ball's covariance is isotropic by symmetry (cubic lattice); the sheet has no
  // extent across.
  EXPECT_NEAR(b.bodies[0].roundness, 1.0, 1e-9);
  EXPECT_LT(b.bodies[1].roundness, 1e-6);
}

TEST(Bodies, LabelsDoNotDependOnTheParticleOrder) {
  std::vector<Vec3> x;
  std::vector<int32_t> phase;
  addBall(x, phase, Vec3(0, 0, 0), 2, 0);
  addBall(x, phase, Vec3(0.1, 0, 0), 2, 1);
  addBall(x, phase, Vec3(0.2, 0, 0), 1, 0);
  const auto a = mf::findBodies(x.data(), phase.data(), x.size(), 1.5 * kSpacing);
  std::vector<size_t> order(x.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = (i * 37) % order.size();  // 37 is coprime with 73
  ASSERT_EQ(std::set<size_t>(order.begin(), order.end()).size(), order.size());
  std::vector<Vec3> y;
  std::vector<int32_t> q;
  for (size_t i : order) y.push_back(x[i]), q.push_back(phase[i]);
  const auto b = mf::findBodies(y.data(), q.data(), y.size(), 1.5 * kSpacing);
  ASSERT_EQ(a.bodies.size(), 3u);
  ASSERT_EQ(b.bodies.size(), a.bodies.size());
  for (size_t k = 0; k < order.size(); ++k) EXPECT_EQ(b.bodyOf[k], a.bodyOf[order[k]]);
}

}  // namespace
