// Conservation laws and the behaviour of the core that have exact or analytic answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

// A free cube of fluid with random velocities, no walls and no gravity: internal forces only.
const char* kFreeCube = R"(
[scene]
name = "free"
end_time = 1.0
frame_rate = 10
domain_min = [-1.0, -1.0, -1.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
particle_spacing = 0.01
[[phase]]
name = "a"
rest_density = 1000.0
stiffness = 100.0
viscosity = 0.2
[[phase]]
name = "b"
rest_density = 600.0
stiffness = 300.0
viscosity = 0.02
[[fluid]]
phase = "a"
jitter = 0.2
min = [0.0, 0.0, 0.0]
max = [0.06, 0.12, 0.12]
[[fluid]]
phase = "b"
jitter = 0.2
min = [0.06, 0.0, 0.0]
max = [0.12, 0.12, 0.12]
[effects.pressure]
[effects.viscosity]
)";

TEST(Physics, LinearMomentumConservedWithoutWallsOrGravity) {
  for (const char* solver : {"wcsph", "dfsph"})
  for (const char* formulation : {"mass", "number"}) {
    mf::Simulation sim(mf::parseScene(kFreeCube, "free", {std::string("solver.density_formulation=") + formulation,
                                                          std::string("solver.pressure=\"") + solver + "\""}));
    std::mt19937_64 rng(5);
    std::normal_distribution<double> n(0, 0.3);
    auto& ps = sim.mutableParticles();
    for (auto& v : ps.velocity) v = {n(rng), n(rng), n(rng)};
    sim.refresh();
    auto momentum = [&] {
      mf::Vec3 p;
      double scale = 0;  // sum |m v|: the size rounding errors are relative to
      for (size_t i = 0; i < sim.particles().size(); ++i) {
        p += sim.particles().velocity[i] * sim.particles().mass[i];
        scale += mf::length(sim.particles().velocity[i]) * sim.particles().mass[i];
      }
      return std::make_pair(p, scale);
    };
    const auto [p0, scale] = momentum();
    for (int k = 0; k < 200; ++k) sim.step(1.0);
    const auto [p1, scale1] = momentum();
    // Pair forces cancel exactly; what remains is the rounding of the sums over ~1700 particles
    // and 200 steps: ~1e-16 relative per operation, far below 1e-10. DFSPH's pressure pairs
    // cancel as exactly, but its implicit viscosity stops at a residual of 1e-6 of |M v| per
    // solve (measured: 7.7e-7 and 1.4e-6 of the scale after 200 steps): 1e-5 bounds that, and an
    // unbalanced pressure force would be orders of magnitude above it.
    const double bound = std::string(solver) == "wcsph" ? 1e-10 : 1e-5;
    EXPECT_LT(mf::length(p1 - p0), bound * scale) << solver << ", " << formulation;
    EXPECT_EQ(sim.counters().retries, 0u);
    (void)scale1;
  }
}

struct BoxRun {
  double growth = 0;  // max over steps of (E - E0) / E0
  double vmax = 0;    // largest speed at the end
  double medianNearest = 0;  // median nearest-neighbour distance at the end, in spacings
};

BoxRun runClosedBox(bool still, double endTime, const std::string& kernel, double cfl = 0.4) {
  // WCSPH: the energy the explicit pressure force and symplectic Euler conserve is measured here.
  mf::Simulation sim(mf::parseScene(mf::closedBoxScene(still), "closed_box",
                                    {"solver.pressure=\"wcsph\"", "solver.kernel=" + kernel, "solver.cfl=" + std::to_string(cfl)}));
  const double e0 = mf::mechanicalEnergy(sim);
  BoxRun r;
  sim.advanceTo(endTime, [&](const mf::Simulation& s) { r.growth = std::max(r.growth, mf::mechanicalEnergy(s) / e0 - 1); });
  const auto& ps = sim.particles();
  std::vector<double> nearest(ps.size(), 1e9);
  for (size_t i = 0; i < ps.size(); ++i) {
    r.vmax = std::max(r.vmax, double(mf::length(ps.velocity[i])));
    for (size_t j = 0; j < ps.size(); ++j)
      if (j != i) nearest[i] = std::min(nearest[i], double(mf::length(ps.position[i] - ps.position[j])));
  }
  std::nth_element(nearest.begin(), nearest.begin() + long(nearest.size() / 2), nearest.end());
  r.medianNearest = nearest[nearest.size() / 2] / sim.scene().solver.particleSpacing;
  std::printf("closed box (%s, %s, cfl %.2f): energy growth %+.2f %%, max speed %.3f m/s, median nearest neighbour %.3f spacings\n",
              still ? "still water" : "drop", kernel.c_str(), cfl, 100 * r.growth, r.vmax, r.medianNearest);
  return r;
}

// A closed, viscous box has no energy source: its energy may only fall. The pressure force of
// the default kernels is conservative, so what remains is symplectic Euler's O(dt) energy error.
// Still water: measured +0.02 % (limit 1 %), 0.12 m/s of acoustic ringing from the seeding
// lattice (limit 0.3 m/s), median nearest neighbour 0.93 spacings (poly6's own gradient
// collapsed it into pairs at 0.06; limit 0.8). The papers' spiky gradient on poly6 densities is
// not conservative: the same still water gains 665 % within 0.6 s, particles reach 7 m/s; the
// test requires that too (> 50 %), so that it can tell the two apart.
TEST(Physics, ClosedBoxOfStillWaterGainsNoEnergy) {
  const BoxRun wendland = runClosedBox(true, 0.6, "wendland");
  EXPECT_LT(wendland.growth, 0.01);
  EXPECT_LT(wendland.vmax, 0.3);
  EXPECT_GT(wendland.medianNearest, 0.8);
  const BoxRun muller = runClosedBox(true, 0.6, "muller2003");
  EXPECT_GT(muller.growth, 0.5) << "the papers' kernels were expected to pump energy into still water";
}

// The drop: the impact overshoots by the integrator's error, which halves with the time step
// (measured +3.7 % at cfl 0.4, +2.0 % at 0.2; the papers' kernels: +96 % at 0.4). Limits: 5 %,
// and halving the step must take off at least 30 % of it (first order: 50 %).
TEST(Physics, ClosedBoxDropGainsOnlyTheIntegratorsError) {
  const BoxRun r = runClosedBox(false, 0.6, "wendland");
  const BoxRun half = runClosedBox(false, 0.6, "wendland", 0.2);
  EXPECT_LT(r.growth, 0.05);
  EXPECT_LT(half.growth, 0.7 * r.growth);
  EXPECT_GT(r.medianNearest, 0.6);  // splashing spreads it (measured 0.78); pairs would be < 0.3
}

// Two fluids layered 1:10 at rest on the seeding lattice, far from walls.
const char* kLayered = R"(
[scene]
name = "layered"
end_time = 1.0
frame_rate = 10
domain_min = [-1.0, -1.0, -1.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
particle_spacing = 0.01
[[phase]]
name = "heavy"
rest_density = 1000.0
[[phase]]
name = "light"
rest_density = 100.0
[[fluid]]
phase = "heavy"
min = [0.0, 0.0, 0.0]
max = [0.16, 0.08, 0.16]
[[fluid]]
phase = "light"
min = [0.0, 0.08, 0.0]
max = [0.16, 0.16, 0.16]
)";

// Largest |rho/rho0 - 1| over particles within one support radius of the interface and at
// least two from every free face of the block.
double interfaceDensityError(const mf::Simulation& sim) {
  const auto& ps = sim.particles();
  const double h = sim.kernels().h;
  double worst = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const mf::Vec3 x = ps.position[i];
    if (std::fabs(x.y - 0.08) > h) continue;
    if (x.x < 2 * h || x.x > 0.16 - 2 * h || x.z < 2 * h || x.z > 0.16 - 2 * h) continue;
    worst = std::max(worst, std::fabs(ps.density[i] / ps.restDensity[i] - 1));
  }
  return worst;
}

TEST(Physics, NumberDensityFixesDensityAtOneToTenInterface) {
  mf::Simulation mass(mf::parseScene(kLayered, "layered", {"solver.density_formulation=mass"}));
  mf::Simulation number(mf::parseScene(kLayered, "layered", {"solver.density_formulation=number"}));
  const double errMass = interfaceDensityError(mass), errNumber = interfaceDensityError(number);
  std::printf("density error at a 1:10 interface: mass summation %.1f %%, number density %.2e %%\n", 100 * errMass,
              100 * errNumber);
  // Eq. (1) gives a light particle next to the interface the mass of its heavy neighbours:
  // several times its rest density. Number density depends on positions only, and the block
  // sits on the lattice the masses were calibrated on: exact to rounding.
  EXPECT_GT(errMass, 1.0);
  EXPECT_LT(errNumber, 1e-9);
}

TEST(Physics, UnusedAttributesAreNotAllocated) {
  mf::Simulation sim(mf::parseScene(kLayered, "layered"));
  const auto& ps = sim.particles();
  EXPECT_FALSE(ps.has(mf::Attribute::Temperature));
  EXPECT_EQ(ps.temperature.capacity(), 0u);
  EXPECT_EQ(ps.interfaceColour.capacity(), 0u);
  EXPECT_EQ(ps.surfaceColour.capacity(), 0u);
  size_t arrays = 0;
  const_cast<mf::ParticleSet&>(ps).forEachArray([&](const char*, const auto&) { ++arrays; });
  EXPECT_EQ(arrays, 13u);  // the core attributes and DFSPH's divergence-free pressure (its warm start)
}

}  // namespace
