// Fluid block shapes (box, sphere, ellipsoid, cylinder), regions subtracted from a block, and
// gravity ramped in: each seeded or moved as its geometry or its formula says.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/scene_budget.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

using mf::Real;
using mf::Vec3;

std::string sceneWith(const std::string& fluid, const std::string& extra = "") {
  return R"([scene]
name = "shapes"
end_time = 0.5
frame_rate = 10
domain_min = [-1.0, -1.0, -1.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
particle_spacing = 0.01
pressure = "dfsph"
[[phase]]
name = "water"
rest_density = 1000.0
[[fluid]]
phase = "water"
)" + fluid + "\n" + extra;
}

constexpr Real kS = 0.01;  // spacing: one particle per s^3 of volume

}  // namespace

TEST(SceneShapes, EllipsoidAndCylinderSeedTheirVolume) {
  {
    const mf::Simulation sim(mf::parseScene(sceneWith("shape = \"ellipsoid\"\ncentre = [0.0, 0.0, 0.0]\nradii = [0.1, 0.05, 0.08]"), "e.toml"));
    const auto& ps = sim.particles();
    for (size_t i = 0; i < ps.size(); ++i) {
      const Vec3 x = ps.position[i];
      ASSERT_LE(x.x * x.x / 0.01 + x.y * x.y / 0.0025 + x.z * x.z / 0.0064, 1.0);
    }
    // 4/3 pi a b c / s^3 = 1 676; a lattice in a smooth body is within a few per cent.
    EXPECT_NEAR(double(ps.size()), 4.0 / 3.0 * M_PI * 0.1 * 0.05 * 0.08 / (kS * kS * kS), 0.03 * 1676);
  }
  {
    const mf::Simulation sim(
        mf::parseScene(sceneWith("shape = \"cylinder\"\nbase = [-0.1, 0.0, 0.0]\nradius = 0.05\nheight = 0.2\naxis = \"x\""), "c.toml"));
    const auto& ps = sim.particles();
    for (size_t i = 0; i < ps.size(); ++i) {
      const Vec3 x = ps.position[i];
      ASSERT_GE(x.x, -0.1);
      ASSERT_LE(x.x, 0.1);
      ASSERT_LE(x.y * x.y + x.z * x.z, 0.05 * 0.05);
    }
    EXPECT_NEAR(double(ps.size()), M_PI * 0.05 * 0.05 * 0.2 / (kS * kS * kS), 0.03 * 1571);
  }
}

TEST(SceneShapes, SubtractedRegionsAreLeftOutAndTheBudgetCountsExactly) {
  const std::string fluid = R"(min = [-0.1, -0.1, -0.1]
max = [0.1, 0.1, 0.1]
[[fluid.subtract]]
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = 0.06
[[fluid.subtract]]
min = [0.05, 0.05, -0.1]
max = [0.1, 0.1, 0.1])";
  const mf::Scene scene = mf::parseScene(sceneWith(fluid), "cut.toml");
  const mf::Simulation sim(scene);
  const auto& ps = sim.particles();
  for (size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.position[i];
    ASSERT_GT(lengthSquared(x), 0.06 * 0.06);
    ASSERT_FALSE(x.x >= 0.05 && x.y >= 0.05);
  }
  // 8 000 lattice points, less the sphere (905) and the 5 x 5 x 20 corner column (500).
  EXPECT_NEAR(double(ps.size()), 8000 - 4.0 / 3.0 * M_PI * 216 - 500, 40);
  EXPECT_EQ(mf::estimateSceneBudget(scene).particles, double(ps.size()));
}

TEST(SceneShapes, ShapeKeysAreChecked) {
  try {
    mf::parseScene(sceneWith("shape = \"cylinder\"\nradius = 0.05\nheight = 0.2\naxis = \"w\""), "bad.toml");
    FAIL() << "accepted";
  } catch (const mf::SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("fluid[0].base"), std::string::npos) << m;
    EXPECT_NE(m.find("fluid[0].axis"), std::string::npos) << m;
  }
  try {
    mf::parseScene(sceneWith("min = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\n[[fluid.subtract]]\nshape = \"torus\""), "bad.toml");
    FAIL() << "accepted";
  } catch (const mf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("fluid[0].subtract[0].shape"), std::string::npos) << e.what();
  }
}

TEST(SceneShapes, GravityRampsInAsItsFormulaSays) {
  // One particle, no walls: y(T) = g T^2 (1/4 - 1/pi^2) for g(t) = g (1 - cos(pi t / T)) / 2,
  // against g T^2 / 2 at full gravity from the start.
  const std::string fluid = "min = [0.0, 0.0, 0.0]\nmax = [0.01, 0.01, 0.01]";
  const std::string gravity = "[effects.gravity]\nramp_time = 0.5\n";
  mf::Simulation sim(mf::parseScene(sceneWith(fluid, gravity), "ramp.toml", {"solver.max_dt=0.001"}));
  ASSERT_EQ(sim.particles().size(), 1u);
  const Real y0 = sim.particles().position[0].y;
  sim.advanceTo(0.5);
  const Real fallen = y0 - sim.particles().position[0].y, expected = 9.81 * 0.25 * (0.25 - 1 / (M_PI * M_PI));
  // Symplectic Euler at 1 ms over 500 steps: within 1 % (measured below).
  EXPECT_NEAR(fallen, expected, 0.01 * expected);
  std::printf("  fell %.5f m, formula %.5f m\n", fallen, expected);
}
