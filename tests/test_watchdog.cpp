// The watchdog: bad steps are retried with a smaller dt, and a run that cannot be saved stops
// with a message naming the step, the particle, its phase and the parameter at fault.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

// The drop of sim/diagnostics.h: a block of water thrown at the floor of a closed box.
const std::string kDrop = mf::closedBoxScene(false);

bool allFinite(const mf::ParticleSet& ps) {
  for (size_t i = 0; i < ps.size(); ++i)
    if (!mf::isFinite(ps.position[i]) || !mf::isFinite(ps.velocity[i]) || !std::isfinite(ps.density[i])) return false;
  return true;
}

TEST(Watchdog, InjectedNaNStopsTheRunNamingTheParticle) {
  mf::Simulation sim(mf::parseScene(kDrop, "drop"));
  sim.advanceTo(0.01);
  const size_t victim = sim.particles().size() / 2;
  const uint64_t victimId = sim.particles().id[victim];
  sim.mutableParticles().velocity[victim].y = std::numeric_limits<double>::quiet_NaN();
  try {
    sim.step(1.0);
    FAIL() << "NaN was not caught";
  } catch (const mf::NumericalInstability& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("particle id " + std::to_string(victimId) + " of phase \"water\""), std::string::npos) << msg;
    EXPECT_NE(msg.find("invalid input"), std::string::npos) << msg;
    EXPECT_NE(msg.find("before step "), std::string::npos) << msg;
  }
}

TEST(Watchdog, TooLargeTimeStepIsRetriedSmaller) {
  // cfl = 10 is 25x the default: a step can move particles by several support radii. The
  // force limit stays at its default: with it 40x too large as well (force_factor = 10),
  // accepted steps at the edge of the limits pump energy into the impact (symplectic Euler
  // beyond its stability limit) until no halving saves a step, and the run stops naming
  // solver.cfl (the next test).
  mf::Simulation sim(mf::parseScene(kDrop, "drop", {"solver.cfl=10.0", "solver.max_dt=0.01"}));
  sim.advanceTo(0.1);
  EXPECT_GT(sim.counters().retries, 0u);
  EXPECT_TRUE(allFinite(sim.particles()));
  EXPECT_LT(sim.counters().maxDensityError, 0.5);
}

TEST(Watchdog, TooLargeTimeStepWithoutRetriesStopsNamingTheParameter) {
  mf::Simulation sim(mf::parseScene(kDrop, "drop", {"solver.cfl=10.0", "solver.force_factor=10.0", "solver.max_dt=0.01", "solver.max_retries=0"}));
  try {
    sim.advanceTo(0.1);
    FAIL() << "unstable step was not caught";
  } catch (const mf::NumericalInstability& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("solver.cfl"), std::string::npos) << msg;
    EXPECT_NE(msg.find("of phase \"water\""), std::string::npos) << msg;
  }
  // The simulation is left at its last valid state.
  EXPECT_TRUE(allFinite(sim.particles()));
}

TEST(Watchdog, AStepCountsTheClampsOfTheMoveItKeeps) {
  // A block thrown at 3 m/s at a wall 2.5 cm away (its front layer), with cfl = 10 and max_dt =
  // 10 ms: the first try of the first step moves it 3 cm, its front layer of 25 particles through
  // the wall (the clamp puts them back on it); that try and the one at 5 ms move particles by more
  // than the watchdog's half support and are thrown away, and the one kept, at 2.5 ms, moves the
  // block 7.5 mm and clamps nothing. The counter tells the user how often particles were put
  // back on a wall, and the moves thrown away did not happen (it used to read 25 here).
  const std::string scene = R"(
[scene]
name = "retried_throw"
end_time = 1.0
domain_min = [-0.1, -0.1, -0.1]
domain_max = [0.3, 0.2, 0.2]
[solver]
particle_spacing = 0.01
cfl = 10.0
max_dt = 0.01
[[phase]]
name = "water"
rest_density = 1000.0
viscosity = 0.001
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.1, 0.1]
[[fluid]]
phase = "water"
min = [0.02, 0.02, 0.02]
max = [0.07, 0.07, 0.07]
velocity = [-3.0, 0.0, 0.0]
[effects.viscosity]
)";
  mf::Simulation sim(mf::parseScene(scene, "retried_throw"));
  sim.step(1.0);
  EXPECT_EQ(sim.counters().retries, 2u);
  EXPECT_DOUBLE_EQ(sim.counters().lastDt, 0.0025);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
  for (size_t i = 0; i < sim.particles().size(); ++i) EXPECT_GT(sim.particles().position[i].x, 0.0) << i;
}

}  // namespace
