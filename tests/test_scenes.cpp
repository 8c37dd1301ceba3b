// Whole scenes: containers are never crossed, and in two_fluids_mixed the light fluid ends on top.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "tests/env_overrides.h"
#include "sim/solids.h"

namespace {

// Water thrown into a glass (open-top cylinder) and into a closed vessel of revolution.
const std::string kHeader = R"(
[scene]
name = "containers"
end_time = 0.4
frame_rate = 10
domain_min = [-0.2, -0.1, -0.2]
domain_max = [0.2, 10.0, 0.2]   # tall: a splash out of the open glass stays counted
[solver]
particle_spacing = 0.008
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 600.0
viscosity = 0.05
[effects.gravity]
[effects.pressure]
[effects.viscosity]
)";
const std::string kGlass = R"(
[[solid]]
name = "glass"
shape = "cylinder"
base = [-0.1, 0.0, 0.0]
radius = 0.05
height = 0.15
open_top = true
[[fluid]]
shape = "sphere"
phase = "water"
centre = [-0.1, 0.06, 0.0]
radius = 0.04
velocity = [0.3, -0.5, 0.5]
)";
const std::string kVessel = R"(
[[solid]]
name = "vessel"
shape = "revolution"
base = [0.1, 0.0, 0.0]
profile = [[0.0, 0.03], [0.05, 0.06], [0.15, 0.03], [0.2, 0.04]]
[[fluid]]
phase = "water"
min = [0.075, 0.03, -0.025]
max = [0.125, 0.12, 0.025]
velocity = [1.5, -2.0, 0.0]
)";

// Counts the particles that end a step outside the container they started in.
struct Crossings {
  uint64_t escaped = 0, clamps = 0;
};

Crossings throwIntoContainers(const std::string& containers, const std::vector<std::string>& overrides) {
  const mf::Scene scene = mf::parseScene(kHeader + containers, "containers", overrides);
  mf::Simulation sim(scene);
  const auto& ps = sim.particles();
  // Which container each particle starts in (by id: ids are stable, arrays get re-sorted).
  std::vector<int> home(ps.size(), -1);
  for (size_t i = 0; i < ps.size(); ++i)
    for (size_t s = 0; s < scene.solids.size(); ++s)
      if (mf::insideFluidRegion(scene.solids[s], ps.position[i])) home[ps.id[i]] = int(s);
  EXPECT_EQ(std::count(home.begin(), home.end(), -1), 0);
  if (std::count(home.begin(), home.end(), -1) > 0) return {~0ull, 0};
  const size_t n0 = ps.size();
  uint64_t escaped = 0;
  std::vector<char> overTheRim(ps.size(), 0);  // left through the open top: free from then on
  sim.advanceTo(scene.endTime, [&](const mf::Simulation& s) {
    for (size_t i = 0; i < s.particles().size(); ++i) {
      const uint32_t id = s.particles().id[i];
      const mf::SolidSpec& c = scene.solids[home[id]];
      const mf::Vec3 x = s.particles().position[i];
      if (mf::aboveOpenTop(c, x)) overTheRim[id] = 1;
      escaped += overTheRim[id] || mf::insideFluidRegion(c, x) ? 0 : 1;
    }
  });
  // Only what left over the rim may leave the domain (it falls past the glass to the floor).
  const auto rimLeavers = uint64_t(std::count(overTheRim.begin(), overTheRim.end(), 1));
  EXPECT_EQ(sim.particles().size() + sim.counters().removedOutOfDomain, n0);
  EXPECT_LE(sim.counters().removedOutOfDomain, rimLeavers);
  std::printf("containers (%s): %llu over the rim, %llu clamps\n", overrides[0].c_str(),
              static_cast<unsigned long long>(rimLeavers), static_cast<unsigned long long>(sim.counters().wallClamps));
  return {escaped, sim.counters().wallClamps};
}

TEST(Scenes, FluidNeverCrossesContainerWalls) {
  // WCSPH: the splash reaches the walls hard enough for the last-resort clamp to act, so the
  // test exercises the clamp rather than passing because nothing came near a wall.
  const Crossings wcsph = throwIntoContainers(kGlass + kVessel, {"solver.pressure=\"wcsph\""});
  EXPECT_EQ(wcsph.escaped, 0u);
  EXPECT_GT(wcsph.clamps, 0u);
}

TEST(Scenes, DfsphHoldsASplashInTheGlassWithoutAClamp) {
  // The glass's throw on DFSPH: the boundary samples in the solve alone keep every particle
  // inside, up to those that leave over the rim. (Not yet the vessel's: its 2.5 m/s throw leaves
  // films at rho/rho0 0.87, without pressure, sliding down the 59-degree cone below the bulge,
  // and those cross it: 3 500 clamps in the steps it keeps, docs/pressure_solvers.md.)
  const Crossings dfsph = throwIntoContainers(kGlass, {"solver.pressure=\"dfsph\""});
  EXPECT_EQ(dfsph.escaped, 0u);
  EXPECT_EQ(dfsph.clamps, 0u);
}

TEST(Scenes, TwoFluidsMixedLightFluidEndsOnTop) {
  // The shipped scene at half its resolution (3000 particles) and 2.5 s.
  std::vector<std::string> sets = {"solver.particle_spacing=0.01", "scene.end_time=2.5"};
  for (const std::string& s : mf::test::overridesFromEnv("MF_TWO_FLUIDS_SET")) sets.push_back(s);  // hand-run trials
  const mf::Scene scene = mf::loadScene("two_fluids_mixed", sets);
  mf::Simulation sim(scene);
  const int light = scene.phaseIndex("light"), heavy = scene.phaseIndex("heavy");
  auto meanHeight = [&](int phase) {
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (sim.particles().phase[i] == phase) {
        sum += sim.particles().position[i].y;
        ++n;
      }
    return sum / n;
  };
  const double gap0 = meanHeight(light) - meanHeight(heavy);
  sim.advanceTo(scene.endTime);
  // Fully separated layers of equal volume have their centres half the fluid depth apart
  // (0.075 m here); mixed at random they coincide. Require 90 % of the way: the layers' own
  // compression and the surface layer move the centres by under a spacing (1 cm, 13 % of the
  // gap); without the scene's hydrostatic reference the gap is 0.062 m (83 %).
  const double gap = meanHeight(light) - meanHeight(heavy);
  std::printf("two_fluids_mixed: centre of light above centre of heavy by %.4f m at start, %.4f m at %.1f s\n", gap0,
              gap, sim.time());
  EXPECT_LT(std::fabs(gap0), 0.01);
  EXPECT_GT(gap, 0.9 * 0.075);
  // And, as issue 23 asks, at most 3 % of the light particles below the heavy fluid's median
  // height (50 % when mixed; 8.9 % without the hydrostatic reference, whose lone light
  // particles stay caged: 3.7 % still at 4.5 s at 0.5 cm).
  std::vector<double> heavyY;
  for (size_t i = 0; i < sim.particles().size(); ++i)
    if (sim.particles().phase[i] == heavy) heavyY.push_back(sim.particles().position[i].y);
  std::nth_element(heavyY.begin(), heavyY.begin() + heavyY.size() / 2, heavyY.end());
  const double median = heavyY[heavyY.size() / 2];
  int lightBelow = 0, lightTotal = 0;
  for (size_t i = 0; i < sim.particles().size(); ++i)
    if (sim.particles().phase[i] == light) {
      ++lightTotal;
      lightBelow += sim.particles().position[i].y < median;
    }
  std::printf("two_fluids_mixed: %d of %d light particles (%.1f %%) below the heavy fluid's median height\n", lightBelow,
              lightTotal, 100.0 * lightBelow / lightTotal);
  EXPECT_LE(lightBelow, lightTotal * 3 / 100);
}

}  // namespace
