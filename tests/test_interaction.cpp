// Fluid-fluid interaction effects (Mueller et al. 2005, section 4) against analytic answers:
// heat diffusion against the erf solution, heat sources against Newton's law, surface tension
// turning a cube into a sphere, interface tension sorting a random mixture, thermal expansion.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include "sim/diagnostics.h"
#include "sim/effects/builtin.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "tests/env_overrides.h"

namespace {

using namespace mf;

const char* kHeader = R"(
[scene]
name = "test"
end_time = 1.0
domain_min = [-1.0, -1.0, -1.0]
domain_max = [1.0, 1.0, 1.0]
)";

// A slab at 0 degrees beside one at 1 degree, particles at rest on the lattice; only heat moves.
Real erfRmsError(Real spacing, Real alpha, Real t, uint64_t* particles = nullptr) {
  const std::string text = std::string(kHeader) + fmt::format(R"(
[solver]
particle_spacing = {s}
max_dt = 1.0
[[phase]]
name = "a"
rest_density = 1000.0
thermal_diffusivity = {alpha}
[[fluid]]
phase = "a"
min = [-0.2, 0.0, 0.0]
max = [0.0, 0.06, 0.06]
temperature = 0.0
[[fluid]]
phase = "a"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.06, 0.06]
temperature = 1.0
[effects.heat_diffusion]
)", fmt::arg("s", spacing), fmt::arg("alpha", alpha));
  Simulation sim(parseScene(text, "erf.toml"));
  sim.advanceTo(t);
  const ParticleSet& ps = sim.particles();
  const Real h = sim.kernels().h;
  Real sum = 0;
  int n = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.position[i];
    // Away from the slab's free faces in y and z (insulating, with fewer neighbours) and from
    // its far ends; the erf solution is for an infinite medium.
    if (x.y < h || x.y > 0.06 - h || x.z < h || x.z > 0.06 - h || std::fabs(x.x) > 0.15) continue;
    const Real exact = 0.5 * (1 + std::erf(x.x / (2 * std::sqrt(alpha * t))));
    sum += (ps.temperature[i] - exact) * (ps.temperature[i] - exact);
    ++n;
  }
  if (particles) *particles = ps.size();
  return std::sqrt(sum / n);
}

TEST(HeatDiffusion, StepMatchesErfSolutionAndConverges) {
  // Diffusion length 2 sqrt(alpha t) = 6.3 cm: 6 and 12 spacings.
  const Real coarse = erfRmsError(0.01, 1e-3, 1.0);
  const Real fine = erfRmsError(0.005, 1e-3, 1.0);
  fmt::print("erf RMS error: spacing 1 cm {:.4f}, 0.5 cm {:.4f}\n", coarse, fine);
  // The issue's bound: 5 % of the unit step (measured 0.49 % and 0.25 %).
  EXPECT_LT(coarse, 0.05);
  EXPECT_LT(fine, 0.05);
  // Halving the spacing must lower the error (measured by a factor 1.9).
  EXPECT_LT(fine, 0.8 * coarse);
}

TEST(HeatDiffusion, SourceFollowsNewtonsLawAndNothingElseIsAllocated) {
  // Insulated particles (alpha = 0) inside a source box approach the held value as
  // T(t) = Ts + (T0 - Ts) exp(-r t); explicit Euler with dt <= 0.5 / r is within r dt of that.
  const std::string text = std::string(kHeader) + R"(
[solver]
particle_spacing = 0.01
max_dt = 0.001
[[phase]]
name = "a"
rest_density = 1000.0
[[fluid]]
phase = "a"
min = [0.0, 0.0, 0.0]
max = [0.04, 0.04, 0.04]
temperature = 10.0
[effects.heat_diffusion]
[[effects.heat_diffusion.source]]
min = [-1.0, -1.0, -1.0]
max = [1.0, 0.02, 1.0]
temperature = 60.0
rate = 2.0
)";
  Simulation sim(parseScene(text, "source.toml"));
  EXPECT_TRUE(sim.particles().has(Attribute::Temperature));
  EXPECT_FALSE(sim.particles().has(Attribute::InterfaceColour));
  EXPECT_FALSE(sim.particles().has(Attribute::SurfaceColour));
  EXPECT_FALSE(sim.particles().has(Attribute::Dye));
  sim.advanceTo(0.5);
  const ParticleSet& ps = sim.particles();
  const Real exact = 60 + (10 - 60) * std::exp(-2 * 0.5);
  for (size_t i = 0; i < ps.size(); ++i) {
    if (ps.position[i].y <= 0.02) EXPECT_NEAR(ps.temperature[i], exact, 0.05) << "id " << ps.id[i];
    else EXPECT_EQ(ps.temperature[i], 10.0);
  }
}

// 27 particles of wax at 60 deg C, beta 0.02 /K from 10 deg C: rho0(T) = 1000 / 2.
const std::string kWaxAt60C = std::string(kHeader) + R"(
[solver]
particle_spacing = 0.01
[[phase]]
name = "wax"
rest_density = 1000.0
thermal_expansion = 0.02
reference_temperature = 10.0
[[fluid]]
phase = "wax"
min = [0.0, 0.0, 0.0]
max = [0.03, 0.03, 0.03]
temperature = 60.0
[effects.thermal_expansion]
)";

TEST(ThermalExpansion, RestDensityFollowsTemperature) {
  Simulation sim(parseScene(kWaxAt60C, "expansion.toml"));
  for (Real rho0 : sim.particles().restDensity) EXPECT_DOUBLE_EQ(rho0, 1000.0 / (1 + 0.02 * 50));
}

// The Boussinesq form keeps the rest density and scales the weight: with no pressure effect the
// particles fall freely at g rho0(T)/rest_density = g / (1 + 0.02 * 50) = g / 2. Symplectic
// Euler integrates a constant acceleration's velocity exactly, so v = a t up to rounding
// (1e-9 m/s: a few hundred steps of double-precision sums).
TEST(ThermalExpansion, BoussinesqKeepsRestDensityAndHalvesTheWeightOfWaxAt60C) {
  // The key lands in [effects.thermal_expansion], the scene's last table.
  const std::string text = kWaxAt60C + "boussinesq = 1\n[effects.gravity]\n";
  Simulation sim(parseScene(text, "boussinesq.toml"));
  sim.advanceTo(0.1);
  const ParticleSet& ps = sim.particles();
  ASSERT_EQ(ps.size(), 27u);
  for (size_t i = 0; i < ps.size(); ++i) {
    EXPECT_DOUBLE_EQ(ps.restDensity[i], 1000.0);
    EXPECT_NEAR(ps.velocity[i].y, -9.81 / 2 * sim.time(), 1e-9);
    EXPECT_NEAR(ps.velocity[i].x, 0.0, 1e-12);
  }
}

// Fraction of particles with a neighbour of the other fluid within 1.2 spacings (the six
// lattice neighbours): a measure of interface area per particle.
Real unlikeContactFraction(const Simulation& sim) {
  const ParticleSet& ps = sim.particles();
  const NeighborLists& nl = sim.fluidNeighbors();
  const Real r2 = std::pow(1.2 * sim.particleSpacing(), 2);
  size_t count = 0;
  for (size_t i = 0; i < ps.size(); ++i)
    for (uint64_t k = nl.begin(i); k < nl.end(i); ++k) {
      const uint32_t j = nl.indices[k];
      if (ps.phase[j] != ps.phase[i] && lengthSquared(ps.position[i] - ps.position[j]) < r2) {
        ++count;
        break;
      }
    }
  return Real(count) / Real(ps.size());
}

Real mixtureContactRatio(Real sigma, Real endTime) {
  const std::string text = std::string(kHeader) + fmt::format(R"(
[solver]
pressure = "wcsph"
particle_spacing = 0.01
max_dt = 0.005
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 200.0
viscosity = 0.3
interface_colour = -0.5
[[phase]]
name = "oil"
rest_density = 1000.0
stiffness = 200.0
viscosity = 0.3
interface_colour = 0.5
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.12, 0.12, 0.12]
[[fluid]]
phases = ["water", "oil"]
fractions = [0.5, 0.5]
seed = 3
min = [0.0, 0.0, 0.0]
max = [0.12, 0.12, 0.12]
[effects.pressure]
[effects.viscosity]
[effects.interface_tension]
sigma = {}
)", sigma);
  Simulation sim(parseScene(text, "mixture.toml"));
  const Real before = unlikeContactFraction(sim);
  sim.advanceTo(endTime);
  return before / unlikeContactFraction(sim);
}

TEST(InterfaceTension, ColourGradientIntegratesToTheJumpAcrossAFlatInterface) {
  // CSF (Brackbill 1992) needs the colour gradient to be a delta function of the interface:
  // across it, the integral of |grad c| is the colour jump (1 from -0.5 to +0.5), and the tension
  // is sigma times that. On the rest lattice (h = 2 spacings, a particle's volume 1 / the kernel
  // sum) the difference-form gradient of each particle in a column through a flat interface is
  // summed, times its volume over the column's area. Poly6's lattice sum reads 1.0689 without the
  // scale (the capillary stress takes it twice: 14 % too much tension); with it, exactly the
  // particle's volume over s^3, 1.0019 (the density kernel's lattice sum is 0.2 % short of 1/s^3).
  const Real s = 0.01;
  const SphKernels K(2 * s, KernelChoice::WendlandC2, s);
  const Real V = 1.0 / latticeKernelSum(K, s);
  const int n = 3;  // neighbours reach 2 spacings: three layers either side cover every pair
  Real integral = 0;
  for (int k = -n; k < n; ++k) {  // the column's particles at z = (k + 1/2) s; the interface at z = 0
    const Real ci = k < 0 ? -0.5 : 0.5;
    Real gz = 0;
    for (int c = -2 * n; c < 2 * n; ++c)
      for (int b = -n; b <= n; ++b)
        for (int a = -n; a <= n; ++a) {
          const Real cj = c < 0 ? -0.5 : 0.5, dz = Real(k - c) * s;  // r_ij = x_i - x_j
          const Real r2 = s * s * Real(a * a + b * b) + dz * dz;
          if (cj == ci || r2 >= K.h2) continue;
          const Real d = K.h2 - r2;
          gz += V * (cj - ci) * (-6 * K.poly6Coef) * d * d * dz;
        }
    integral += V * gz / (s * s);
  }
  const Real scale = effects::colourGradientScale(K, s);
  std::printf("flat interface: lattice M %.4f; integral of |grad c| %.4f, with the scale %.6f (V / s^3 %.6f)\n", 1 / scale, integral,
              integral * scale, V / (s * s * s));
  EXPECT_NEAR(integral, 1.0689, 5e-4);
  EXPECT_NEAR(integral * scale, V / (s * s * s), 1e-9);
  EXPECT_NEAR(V / (s * s * s), 1.0, 0.003);
}

TEST(InterfaceTension, RandomMixtureSortsItself) {
  // Equal densities, no gravity: only interface tension can sort the fluids; the issue asks the
  // unlike-contact fraction to fall 5x. Measured with sigma = 1.71 N/m: 7.32x in 4.2 s. That is
  // the tension the key 1.5 gave before the colour gradient's lattice calibration, with which
  // it read 1.85x at 1 s, 4.95x at 3 s, 5.9x at 4 s, 6.7x at 5 s. (With 0.6 it was 6.0x at 4.2 s
  // under the papers' kernels, whose non-conservative pressure stirred the particles; with the
  // conservative default it is 3.5x: coarsening is driven by tension alone.) On WCSPH: the lattice filling a
  // closed box is held on its sites by DFSPH's constant-density solve, 1.00x at 2 spacings'
  // support, 2.37x at 2.25 and 3.24x at 2.5 (docs/pressure_solvers.md).
  const Real ratio = mixtureContactRatio(1.71, 4.2);
  std::printf("random mixture: unlike contacts fell %.2fx in 4.2 s\n", ratio);
  EXPECT_GT(ratio, 5.0);
  // Without it nothing sorts (the particles stay where they were seeded).
  EXPECT_LT(mixtureContactRatio(0.0, 1.0), 1.2);
}

TEST(InteractionScenes, PairsSourcesAndUnusedPhaseKeysAreChecked) {
  const std::string base = std::string(kHeader) + R"(
[solver]
particle_spacing = 0.01
[[phase]]
name = "water"
rest_density = 1000.0
thermal_diffusivity = 1e-6
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.03, 0.03, 0.03]
)";
  try {
    parseScene(base, "unused.toml");
    FAIL() << "a diffusivity without [effects.heat_diffusion] must be reported";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("unused.toml:13: key 'phase[0].thermal_diffusivity': has no effect unless [effects.heat_diffusion]"),
              std::string::npos)
        << e.what();
  }
  const std::string bad = base + R"(
[effects.heat_diffusion]
[[effects.heat_diffusion.source]]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
temperature = 50.0
[effects.interface_tension]
[[effects.interface_tension.pair]]
phases = ["water", "oill"]
sigma = 0.1
)";
  try {
    parseScene(bad, "bad.toml");
    FAIL() << "missing rate and unknown phase must be reported";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("key 'effects.heat_diffusion.source[0].rate': missing"), std::string::npos) << what;
    EXPECT_NE(what.find("bad.toml:26: key 'effects.interface_tension.pair[0].phases': unknown phase \"oill\"; defined: \"water\""),
              std::string::npos)
        << what;
  }
}

}  // namespace

namespace {

// Oil and water after settling. Bodies: oil particles linked closer than 1.5 spacings (as the
// surfacing links a body), the oil layer the largest. An oil particle is stranded when water
// lies above it (a water particle higher up within one spacing of its vertical) and it is not
// part of the oil layer; "isolated" when, in addition, no oil particle is within 2 spacings.
struct OilAndWater {
  double oilHeight = 0, waterHeight = 0;  // centres of mass, m
  int stranded = 0, isolated = 0, bodies = 0, layer = 0;
};
OilAndWater oilAndWater(const Simulation& sim, int oil, int water) {
  const ParticleSet& ps = sim.particles();
  const size_t n = ps.size();
  const Real s = sim.particleSpacing();
  OilAndWater r;
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  const NeighborLists& nl = sim.fluidNeighbors();
  int oils = 0, waters = 0;
  for (size_t i = 0; i < n; ++i) {
    if (ps.phase[i] == water) r.waterHeight += ps.position[i].y, ++waters;
    if (ps.phase[i] != oil) continue;
    r.oilHeight += ps.position[i].y, ++oils;
    for (uint64_t k = nl.begin(i); k < nl.end(i); ++k) {
      const uint32_t j = nl.indices[k];
      if (ps.phase[j] == oil && length(ps.position[i] - ps.position[j]) < 1.5 * s) parent[find(uint32_t(i))] = find(j);
    }
  }
  r.oilHeight /= oils;
  r.waterHeight /= waters;
  std::vector<int> size(n, 0);
  for (size_t i = 0; i < n; ++i)
    if (ps.phase[i] == oil) ++size[find(uint32_t(i))], r.bodies += find(uint32_t(i)) == i;
  const uint32_t layer = uint32_t(std::max_element(size.begin(), size.end()) - size.begin());
  r.layer = size[layer];
  for (size_t i = 0; i < n; ++i) {
    if (ps.phase[i] != oil || find(uint32_t(i)) == layer) continue;
    bool waterAbove = false, oilNear = false;
    for (size_t j = 0; j < n; ++j) {
      const Vec3 d = ps.position[j] - ps.position[i];
      waterAbove |= ps.phase[j] == water && d.y > 0 && d.x * d.x + d.z * d.z < s * s;
      oilNear |= j != i && ps.phase[j] == oil && lengthSquared(d) < 4 * s * s;
    }
    r.stranded += waterAbove;
    r.isolated += waterAbove && !oilNear;
  }
  return r;
}

// The issue: oil and water shaken together separate into two layers, oil on top, and no oil
// particle is left stranded inside the water after settling. Run at 1 cm spacing (3000
// particles; the scene ships 0.75 cm) over the scene's 8 s, on the scene's DFSPH with the
// hydrostatic reference in the solve: the oil's centre 0.0764 m above the water's, one oil
// body, none stranded or isolated. Without the reference, 0.0101 m, 4 oil bodies, 3 stranded
// (docs/pressure_solvers.md). On WCSPH with the reference and the gradient correction: 0.0757 m.
// Bound: two layers of equal volume 0.15 m deep in all have centres 0.075 m apart; 90 % of
// that leaves room for the oil layer's meniscus and the water held at its rim (17 particles).
// It holds off its exact parameters: with the water's viscosity moved by 1e-4 to 1e-2 of itself
// either way (WaterOilSeries.DISABLED_Profile, MF_WATER_OIL_SET, 8 runs) the gap read
// 0.0763-0.0765 m, one oil body, none stranded or isolated, in every run.
TEST(WaterOilScene, OilSettlesOnTopAndNoneIsStranded) {
  const Scene scene = loadScene("water_oil", {"solver.particle_spacing=0.01"});
  Simulation sim(scene);
  const int oil = scene.phaseIndex("oil"), water = scene.phaseIndex("water");
  sim.advanceTo(scene.endTime);
  const OilAndWater r = oilAndWater(sim, oil, water);
  fmt::print("water_oil at {} s: oil centre {:.4f} m, water centre {:.4f} m; {} oil bodies, layer {}, {} stranded, {} isolated\n",
             sim.time(), r.oilHeight, r.waterHeight, r.bodies, r.layer, r.stranded, r.isolated);
  EXPECT_GT(r.oilHeight - r.waterHeight, 0.9 * 0.075);
  EXPECT_EQ(r.stranded, 0);
  EXPECT_EQ(r.isolated, 0);
}

}  // namespace

// Diagnostic, not a check (DISABLED, run by hand): the water_oil scene's separation over time,
// with the oil's volume fraction per 1 cm of height, so that parameter trials can be read
// without a renderer. MF_WATER_OIL_SET holds ';'-separated --set overrides, MF_WATER_OIL_EVERY
// the reporting interval in s (1). Example (one thread, about 70 s at 1.5 cm for 12 s):
//   MF_WATER_OIL_SET='solver.particle_spacing=0.015;scene.end_time=12' taskset -c 0
//     ./build-h1/tests/mf_tests --gtest_also_run_disabled_tests --gtest_filter='WaterOilSeries.*'
namespace {
using namespace mf;
TEST(WaterOilSeries, DISABLED_Profile) {
  const std::vector<std::string> ovr = test::overridesFromEnv("MF_WATER_OIL_SET");
  const Scene scene = loadScene("water_oil", ovr);
  Simulation sim(scene);
  const int oil = scene.phaseIndex("oil"), water = scene.phaseIndex("water");
  const double every = std::getenv("MF_WATER_OIL_EVERY") ? std::atof(std::getenv("MF_WATER_OIL_EVERY")) : 1.0;
  for (double t = every; t <= scene.endTime + 1e-9; t += every) {
    sim.advanceTo(t);
    const OilAndWater r = oilAndWater(sim, oil, water);
    fmt::print("t {:.1f} gap {:.4f} bodies {} layer {} stranded {} isolated {}\n", sim.time(),
               r.oilHeight - r.waterHeight, r.bodies, r.layer, r.stranded, r.isolated);
    const ParticleSet& ps = sim.particles();
    std::vector<int> no(40, 0), nw(40, 0);
    for (size_t i = 0; i < ps.size(); ++i) {
      const int b = std::clamp(int(ps.position[i].y / 0.01), 0, 39);
      if (ps.phase[i] == oil) ++no[b];
      if (ps.phase[i] == water) ++nw[b];
    }
    std::string prof;
    for (int b = 0; b < 20; ++b) prof += fmt::format(" {:.2f}", no[b] + nw[b] ? double(no[b]) / (no[b] + nw[b]) : -1.0);
    fmt::print("  oil fraction by cm:{}\n", prof);
    std::fflush(stdout);
  }
}
}  // namespace
