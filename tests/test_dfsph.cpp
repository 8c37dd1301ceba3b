// The implicit pressure solver (solver.pressure = "dfsph", sim/pressure/dfsph.h), as far as it is
// built: stable, converged, clamp-free and deterministic, with walls calibrated on the seeding
// lattice (calibrateImplicitWall, sim/solids.h). Its accuracy targets (a still tank at 1e-3 m/s,
// hydrostatic pressure within 1 %) are not met yet; docs/pressure_solvers.md gives the measured
// figures and what stands in the way.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/solids.h"

namespace {

using mf::Real;

// Water 10 cm deep in a closed 20 x 30 x 20 cm box at 1 cm spacing (4 000 particles).
const char* kStillTank = R"([scene]
name = "still"
end_time = 1.0
frame_rate = 10
domain_min = [-0.05, -0.05, -0.05]
domain_max = [0.25, 0.35, 0.25]
[solver]
particle_spacing = 0.01
pressure = "dfsph"
max_dt = 0.005
[[phase]]
name = "water"
rest_density = 1000.0
viscosity = 0.01
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.3, 0.2]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.1, 0.2]
[effects.gravity]
acceleration = [0.0, -9.81, 0.0]
[effects.viscosity]
)";

std::string stateBytes(mf::Simulation& sim) {
  std::string bytes;
  sim.mutableParticles().forEachArray([&](const char*, const auto& v) {
    bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  });
  return bytes;
}

// Tests that run on both linear iterations of the solves (solver.pressure_iteration).
class DfsphIteration : public ::testing::TestWithParam<const char*> {
 protected:
  std::string iteration() const { return std::string("solver.pressure_iteration=\"") + GetParam() + "\""; }
};

TEST_P(DfsphIteration, StillTankStaysAtRestDensityWithoutClampsAndTheStepIsSetByTheFlow) {
  mf::Simulation sim(mf::parseScene(kStillTank, "still.toml", {iteration()}));
  Real worstMean = 0;
  sim.advanceTo(1.0, [&](const mf::Simulation& s) {
    worstMean = std::max(worstMean, std::fabs(s.counters().lastDensityError));
  });
  const auto& c = sim.counters();
  const auto& ps = sim.particles();
  Real vmax = 0, mean = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    vmax = std::max(vmax, length(ps.velocity[i]));
    mean += ps.density[i] / ps.restDensity[i] - 1;
  }
  mean /= Real(ps.size());
  // Every step's solve converged to the 0.05 % tolerance (else it would have been retried).
  EXPECT_LE(worstMean, 5e-4);
  EXPECT_EQ(c.retries, 0u);
  // The mean density error over all particles (the surface layer reads low) stays within 0.2 %.
  EXPECT_LT(std::fabs(mean), 2e-3);
  // Walls inside the solve: no particle needed the last-resort clamp.
  EXPECT_EQ(c.wallClamps, 0u);
  // No sound speed: at most 5 ms steps (max_dt), about 200 steps for 1 s where WCSPH at
  // k = 1000 takes 1 s / (0.4 h / c) = 1 250 or more.
  EXPECT_LE(c.steps, 260u);
  // Measured 0.11 m/s: surface particles still jitter (the 1e-3 m/s target is open); the
  // bound catches a solver that blows up (before the relaxation: 7 700 m/s at step 5).
  EXPECT_LT(vmax, 0.3);
}

// The walls are one term of each particle's density, and their pressure force is that term's
// gradient (calibrateImplicitWall), so the pressure does no work over a closed path: a closed tank
// at rest can only lose energy, to viscosity. Energy per kg (kinetic plus g y), every 0.1 s for
// 2 s: measured at most 1.4e-4 J/kg above the start (0.2 s, while the corners' overshoot is pushed
// out) and 1.9e-4 J/kg below it at 2 s. The wall before, weighted 1.7 times in the force and the
// density rate but not in the density, gained 1.8e-3 J/kg by 2 s and was still rising. Bounds:
// 3e-4 J/kg (0.06 % of the column's g H / 2 = 0.49 J/kg) and a loss by 2 s.
TEST(Dfsph, AStillTankGainsNoEnergy) {
  mf::Simulation sim(mf::parseScene(kStillTank, "still.toml", {"scene.end_time=2"}));
  auto energy = [&] {
    const auto& ps = sim.particles();
    Real e = 0, m = 0;
    for (size_t i = 0; i < ps.size(); ++i) {
      e += ps.mass[i] * (0.5 * lengthSquared(ps.velocity[i]) + 9.81 * ps.position[i].y);
      m += ps.mass[i];
    }
    return e / m;
  };
  const Real start = energy();
  Real gain = 0;
  for (int k = 1; k <= 20; ++k) {
    sim.advanceTo(0.1 * k);
    gain = std::max(gain, energy() - start);
  }
  fmt::print("still tank: energy at most {:.2e} J/kg above the start, {:+.2e} J/kg at 2 s\n", gain, energy() - start);
  EXPECT_LT(gain, 3e-4);
  EXPECT_LT(energy(), start);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
}

TEST(Dfsph, WallsHoldTheSeededLatticeAtRestDensityAndInBalance) {
  mf::Simulation sim(mf::parseScene(kStillTank, "still.toml"));
  const auto& ps = sim.particles();
  // The first layer against the floor and the side walls (half a spacing from each) starts at
  // rest density: the calibrated layer stands in for the missing fluid. Measured 1.0000-1.0001
  // against one wall. Where two or three sample layers overlap the calibration (made for a flat
  // wall) overshoots: 1.0084 along the edges and 1.0248 in the corners (with the old mirror-factor
  // wall, shallower and flatter, 1.003 and 1.011).
  Real faceLo = 2, faceHi = 0, junctionHi = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const mf::Vec3 x = ps.position[i];
    const int walls = (x.y < 0.01) + (x.x < 0.01 || x.x > 0.19) + (x.z < 0.01 || x.z > 0.19);
    if (walls == 0 || x.y > 0.085) continue;  // leave out the free surface layer
    const Real theta = ps.density[i] / ps.restDensity[i];
    if (walls == 1) faceLo = std::min(faceLo, theta), faceHi = std::max(faceHi, theta);
    else junctionHi = std::max(junctionHi, theta);
  }
  EXPECT_GT(faceLo, 0.999);
  EXPECT_LT(faceHi, 1.001);
  EXPECT_LT(junctionHi, 1.03);
  // One step from rest: the seeded hydrostatic pressure and the calibrated wall hold the column,
  // so the rms speed stays well below g dt = 0.049 m/s. Measured 0.0076 m/s in 7 iterations; the
  // 108 edge and corner particles, their overshoot pushed out, hold 46 % of the kinetic energy
  // (rms 0.031 m/s; the interior 0.0051). With SPlisHSPlasH's uncalibrated wall and a
  // zero start 0.037 m/s in 39 (the first layer pulled into the floor, the layers above
  // alternating up and down).
  sim.step(1.0);
  Real sum = 0;
  for (size_t i = 0; i < ps.size(); ++i) sum += lengthSquared(ps.velocity[i]);
  EXPECT_LT(std::sqrt(sum / Real(ps.size())), 0.2 * 9.81 * 0.005);
  EXPECT_LE(sim.counters().pressureIterations, 20u);
}

TEST_P(DfsphIteration, ALoneDropComesToRestOnTheFloorWithoutAClamp) {
  // One particle falls 20 cm (2 m/s at impact): the wall alone must stop it, with no fluid
  // around to make a pressure. It rests where the wall alone reads rest density, which the
  // calibration puts 0.24 spacings above the floor (WallCalibration::contactHeight).
  mf::Simulation sim(mf::parseScene(kStillTank, "drop.toml", {"fluid.0.min=[0.1,0.2,0.1]", "fluid.0.max=[0.11,0.21,0.11]", iteration()}));
  ASSERT_EQ(sim.particles().size(), 1u);
  sim.advanceTo(1.0);
  const auto& ps = sim.particles();
  EXPECT_EQ(sim.counters().wallClamps, 0u);
  // The calibration's contact height on this tank's lattice (h = 2 cm, samples 5 mm apart):
  // 2.44 mm. Measured y = 0.00244 m after 1 s; the bound is a twentieth of a spacing.
  const mf::WallCalibration wall = mf::calibrateImplicitWall(mf::SphKernels(0.02, mf::KernelChoice::WendlandC2, 0.01), 0.01, 0.005);
  EXPECT_NEAR(ps.position[0].y, wall.contactHeight, 0.0005);
  EXPECT_LT(length(ps.velocity[0]), 1e-3);
}

TEST(Dfsph, DamBreakNeedsNoWallClamp) {
  // The shipped dam break (8 192 particles, the front hits the far wall at 1.7 m/s and climbs to
  // the lid), frame by frame as the pipeline advances. Before the calibrated wall: 13 196 clamps.
  // On the default iteration only: projected Jacobi clamps twice, at 0.248 s in the lid's corners
  // (a particle left 27 % compressed at 1 450 Pa, moving 2.5 m/s along the wall).
  mf::Simulation sim(mf::loadScene("dam_break", {"solver.pressure=\"dfsph\""}));
  // A frame's last step is no sliver: the constant-density solve turns the compression a step
  // starts with into a velocity of order 1/dt (a 0.13 ms step before a frame's time once sent
  // a particle off a wall at 11 m/s). Its last two steps are even halves where under two flow
  // steps are left, so each is at least about half the step before them (the flow step changes
  // little from one step to the next). Measured over these 18 frames: 1.000 at worst, 0.083
  // before the halves.
  Real last = 0, worstRatio = 1;
  for (int frame = 1; frame <= 18; ++frame) {
    Real beforeLast = 0;
    sim.advanceTo(frame / 30.0, [&](const mf::Simulation& s) {
      beforeLast = last;
      last = s.counters().lastDt;
    });
    if (beforeLast > 0) worstRatio = std::min(worstRatio, last / beforeLast);
  }
  fmt::print("dam break: a frame's last step is at least {:.3f} of the step before it\n", worstRatio);
  EXPECT_GT(worstRatio, 0.4);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
  EXPECT_EQ(sim.particles().size(), 8192u);
  // The linear solve alone left a particle 24.7 % compressed where the front meets the walls;
  // the passes at the moved positions hold solver.max_compression (1 %). 0.5 % over the bound
  // allows for the rare step whose fifth pass still leaves more (at the 5 % bound and three
  // passes: 4.92 %).
  fmt::print("dam break: worst compression after a step {:.3f} %, {} compression passes\n",
             100 * sim.counters().maxDensityError, sim.counters().compressionPasses);
  EXPECT_LT(sim.counters().maxDensityError, 0.015);
  EXPECT_GT(sim.counters().compressionPasses, 0u);
}

// A constant-density solve that runs out of iterations hands its pressure to the retry
// (sim/simulation_dfsph.cpp). The dam break's column at 3.4 mm (about 10 000 particles) needs 10
// iterations in its first step, as the solve turns the seeded column pressure into the
// collapse's (a free face has none); capped at 6, the first try at 2 ms stops short and the step
// is retried at 1 ms. From the first try's pressure the retry converges in the minimum 2
// iterations, 8 in all; from the seed it took all 6 again, 12 in all. (The shipped dam break at
// 300 000 particles: 1 retry in its first frame instead of 3; at 1 M, 3 instead of 6.)
TEST(Dfsph, ARetryGoesOnFromThePressureTheSolveReached) {
  mf::Simulation sim(mf::loadScene("dam_break", {"solver.particle_spacing=0.0033618", "solver.max_pressure_iterations=6"}));
  sim.step(1.0);
  fmt::print("first step: {} retries, dt {} s, {} constant-density iterations over its tries\n", sim.counters().retries,
             sim.counters().lastDt, sim.counters().pressureIterations);
  EXPECT_EQ(sim.counters().retries, 1u);
  EXPECT_DOUBLE_EQ(sim.counters().lastDt, 0.001);
  EXPECT_LE(sim.counters().pressureIterations, 6u + 2u);
}

// Issue 21: layered fluids at rest stay at rest at 1:10 and 1:1000 (water and air). The still
// tank's 10 cm as 5 cm of water under 5 cm of a fluid 10 or 1000 times lighter (1 cm spacing,
// number density, the default solver and iteration), for 1 s.
struct Layers {
  Real heavyMean = 0, heavyTop = 0, lightBottom = 1, heavySpeed = 0, lightSpeed = 0, heavyDensity = 0;
  uint64_t retries = 0, clamps = 0;
};

Layers layersAtRest(int ratio) {
  std::string text = kStillTank;
  auto replace = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
  replace("max = [0.2, 0.1, 0.2]", "max = [0.2, 0.05, 0.2]");  // the water: its lower half
  replace("pressure = \"dfsph\"\n", "density_formulation = \"number\"\n");  // the default solver
  text += fmt::format("[[phase]]\nname = \"light\"\nrest_density = {}\nviscosity = 0.0001\n", 1000.0 / ratio);
  text += "[[fluid]]\nphase = \"light\"\nmin = [0.0, 0.05, 0.0]\nmax = [0.2, 0.1, 0.2]\n";
  mf::Simulation sim(mf::parseScene(text, "layers.toml"));
  sim.advanceTo(1.0);
  const auto& ps = sim.particles();
  const int light = sim.scene().phaseIndex("light");
  Layers l;
  int heavy = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Real y = ps.position[i].y, v = length(ps.velocity[i]);
    if (ps.phase[i] == light) {
      l.lightBottom = std::min(l.lightBottom, y), l.lightSpeed = std::max(l.lightSpeed, v);
    } else {
      l.heavyMean += y, l.heavyTop = std::max(l.heavyTop, y), l.heavySpeed = std::max(l.heavySpeed, v);
      l.heavyDensity += ps.density[i] / ps.restDensity[i] - 1, ++heavy;
    }
  }
  l.heavyMean /= heavy, l.heavyDensity /= heavy;
  l.retries = sim.counters().retries, l.clamps = sim.counters().wallClamps;
  fmt::print("layers 1:{} after 1 s: water mean height {:.5f} m, top {:.4f} m, fastest {:.4f} m/s, mean rho/rho0 - 1 "
             "{:+.5f}; light bottom {:.4f} m, fastest {:.3f} m/s; {} retries, {} clamps\n",
             ratio, l.heavyMean, l.heavyTop, l.heavySpeed, l.heavyDensity, l.lightBottom, l.lightSpeed, l.retries, l.clamps);
  return l;
}

TEST(Dfsph, LayeredFluidsAtRestStayAtRestAtOneToTenAndOneToAThousand) {
  for (int ratio : {10, 1000}) {
    const Layers l = layersAtRest(ratio);
    EXPECT_EQ(l.retries, 0u);
    EXPECT_EQ(l.clamps, 0u);
    // The water layer stays where it was seeded, at its rest density, under the light one:
    // measured centre 0.02502 / 0.02498 m (seeded 0.025; bound a twentieth of a spacing), top
    // particle 0.0465 / 0.0462 m (seeded 0.045; bound the interface, 0.05), mean rho/rho0 - 1
    // +8e-5 / -2e-5 (bound the issue's 0.1 %), lowest light particle 0.0527 / 0.0569 m (seeded
    // 0.055; bound the water's top layer). Not still: the water's fastest particle moves at 0.044
    // / 0.091 m/s, the still tank's noise (docs/pressure_solvers.md), and the 1:1000 air at
    // 0.42 m/s, its lowest particle 1.1 cm above the water's top; the speed bounds catch a solve
    // that blows up.
    EXPECT_NEAR(l.heavyMean, 0.025, 5e-4);
    EXPECT_LT(l.heavyTop, 0.05);
    EXPECT_GT(l.lightBottom, 0.045);
    EXPECT_LT(std::fabs(l.heavyDensity), 1e-3);
    EXPECT_LT(l.heavySpeed, 0.3);
    EXPECT_LT(l.lightSpeed, 1.0);
  }
}

// A heavy layer over a light one: the report's layered problem (mf::layeredScene: Rayleigh-Taylor,
// 1000 over 500 kg/m^3, 6 cm each, mu = 0.5 Pa s, jittered by 0.1 spacing) at 1 cm, with the
// hydrostatic reference the shipped two-fluid scenes carry, on DFSPH (named: the scene's stiffness
// keys are WCSPH's, and a scene that carries them must name its solver).
TEST(Dfsph, AHeavyLayerOverALightOneOverturnsWithTheHydrostaticReference) {
  mf::Simulation sim(mf::parseScene(mf::layeredScene(0.01, "mass", true, 4.0), "overturn.toml", {"solver.pressure=\"dfsph\""}));
  ASSERT_EQ(sim.scene().solver.pressure, mf::PressureSolverChoice::DFSPH);
  const int heavy = sim.scene().phaseIndex("heavy");
  auto wrongSide = [&] { return mf::massOnTheWrongSide(sim.particles(), heavy, sim.particleSpacing()).fraction(); };
  const Real start = wrongSide();
  sim.advanceTo(2.0);
  const Real atTwo = wrongSide();
  sim.advanceTo(4.0);
  const Real atFour = wrongSide();
  fmt::print("wrong side: {:.1f} % at 0 s, {:.2f} % at 2 s, {:.2f} % at 4 s; {} retries, {} clamps\n", 100 * start,
             100 * atTwo, 100 * atFour, sim.counters().retries, sim.counters().wallClamps);
  EXPECT_GT(start, 0.9);  // seeded upside down: all but what lies within half a spacing of the level (91.8 %)
  // Viscous Rayleigh-Taylor at Atwood 1/3, nu = 6.7e-4 m^2/s: the fastest mode grows at about
  // 10 /s (wavelength about 3 cm), so 1 mm of seeded jitter reaches the layers' 6 cm in about
  // 0.6 s, and the sorted layers have settled by 2 s. Measured 0.83 % at 2 s and 0 at 4 s (without
  // the reference the pressure's rigidity cages light particles near the floor: 27 % and 19 %,
  // docs/pressure_solvers.md); one light particle is 0.09 % of the mass, so 1 % at 4 s allows a
  // few stragglers and 5 % at 2 s a late start.
  EXPECT_LT(atTwo, 0.05);
  EXPECT_LT(atFour, 0.01);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
}

// A simulation of `scene` restored from `first`'s checkpoint and advanced to `t`.
static mf::Simulation resumedFrom(const mf::Scene& scene, const mf::Simulation& first, double t) {
  const std::string path = (std::filesystem::temp_directory_path() / ("mf_dfsph_" + std::to_string(::getpid()) + ".bin")).string();
  first.saveCheckpoint(path, 1);
  mf::Simulation resumed(scene);
  resumed.loadCheckpoint(path);
  resumed.advanceTo(t);
  std::filesystem::remove(path);
  return resumed;
}

TEST_P(DfsphIteration, SameBitsOnOneAndTwoThreadsAndAfterResume) {
  const mf::Scene scene = mf::loadScene("dam_break", {"solver.pressure=\"dfsph\"", "solver.particle_spacing=0.00714",
                                                      iteration()});
  // Frames at 0.05 and 0.1 s, as the pipeline advances (each advanceTo lands on its time).
  auto run = [&](int threads, double t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    mf::Simulation sim(scene);
    sim.advanceTo(0.05);
    if (t > 0.05) sim.advanceTo(t);
    return sim;
  };
  mf::Simulation one = run(1, 0.1), two = run(2, 0.1);
  EXPECT_GT(one.counters().pressureIterations, 0u);
  EXPECT_EQ(stateBytes(one), stateBytes(two));
  // The warm-start pressures are particle arrays: checkpointed and restored with the rest.
  mf::Simulation resumed = resumedFrom(scene, run(2, 0.05), 0.1);
  EXPECT_EQ(stateBytes(resumed), stateBytes(one));
}

INSTANTIATE_TEST_SUITE_P(Dfsph, DfsphIteration, ::testing::Values("jacobi", "cg"));

// A pass on compression sums the density over the move's neighbour lists; the frame then searches
// again at the positions reached, as loadCheckpoint does. A bound of 0.01 % makes passes run in
// nearly every step, so the step before the checkpoint ran some.
TEST(Dfsph, ResumeAfterCompressionPassesIsBitIdentical) {
  const mf::Scene scene = mf::loadScene("dam_break", {"solver.pressure=\"dfsph\"", "solver.particle_spacing=0.00714",
                                                      "solver.max_compression=0.0001"});
  mf::Simulation straight(scene);
  straight.advanceTo(0.05);
  EXPECT_GT(straight.counters().compressionPasses, straight.counters().steps / 2);
  mf::Simulation resumed = resumedFrom(scene, straight, 0.1);
  straight.advanceTo(0.1);
  EXPECT_EQ(stateBytes(resumed), stateBytes(straight));
}

// The hydrostatic reference covers the particles inside the scene's containers only: the
// column it describes is the liquid's in its container. A block of light gas (1 kg/m^3) beside
// the tank and below the level, as boiling's flames lie under its glass, falls freely; covered,
// it would be lifted at rho_ref / rho0 - 1 = 999 g. The water in the tank stays at rest. Bounds:
// the gas block's mean vertical velocity after 0.05 s within 1 % of -g t (its own pressure
// forces cancel in the mean), and the water slower than the still tank's 0.3 m/s bound above.
TEST(Dfsph, TheHydrostaticReferenceLeavesParticlesOutsideTheContainersAlone) {
  std::string scene = kStillTank;
  scene.replace(scene.find("domain_min = [-0.05, -0.05, -0.05]"), 34, "domain_min = [-0.05, -0.5, -0.05]");
  scene.replace(scene.find("domain_max = [0.25, 0.35, 0.25]"), 31, "domain_max = [0.45, 0.35, 0.25]");
  scene += R"([[phase]]
name = "gas"
rest_density = 1.0
viscosity = 0.0
[[fluid]]
phase = "gas"
min = [0.3, 0.0, 0.05]
max = [0.35, 0.05, 0.1]
[effects.pressure]
reference_density = 1000.0
reference_level = 0.095
)";
  mf::Simulation sim(mf::parseScene(scene, "reference_scope.toml"));
  const int gas = sim.scene().phaseIndex("gas");
  const Real t = 0.05;
  sim.advanceTo(t);
  const auto& ps = sim.particles();
  Real vy = 0, waterMax = 0;
  size_t n = 0;
  for (size_t i = 0; i < ps.size(); ++i)
    if (ps.phase[i] == gas) vy += ps.velocity[i].y, ++n;
    else waterMax = std::max(waterMax, length(ps.velocity[i]));
  ASSERT_GT(n, 0u);
  vy /= Real(n);
  fmt::print("reference scope: gas block's mean vy {:.4f} m/s (free fall {:.4f}), water at most {:.4f} m/s\n", vy, -9.81 * t,
             waterMax);
  EXPECT_NEAR(vy, -9.81 * t, 0.01 * 9.81 * t);
  EXPECT_LT(waterMax, 0.3);
}

}  // namespace
