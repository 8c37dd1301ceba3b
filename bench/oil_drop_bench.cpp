// oil_drop_bench: how round a small oil drop of the shipped water_oil scene is while it rises
// through still water (issue 23: "small oil droplets are round"; in the shipped run the oil ends in
// one layer, so no drop of 20-200 particles is left to measure once it has settled).
//
// The liquids, their viscosities, the interface tension, the spacing and the solver settings are
// read from the embedded water_oil scene; only the geometry is the bench's: a tank W x 0.3 x W
// (default W = 0.2 m) of water 0.25 m deep, with one oil ball of N particles, centred 0.07 m
// above the floor. It prints, every 0.1 s, the oil's bodies (linked within 1.5 spacings, as
// body_stats counts them), the largest one's roundness (sqrt of the smallest over the largest
// eigenvalue of its particles' position covariance, 1 for a ball; body_stats's "round"), its
// centroid and rise speed. At the end: the mean roundness over the steady rise (once the drop
// has risen one diameter, until its top is a diameter below the water's surface), the drop's
// Eotvos number Eo = drho g d^2 / sigma, Reynolds number Re = rho U d / mu and Weber number
// We = rho U^2 d / sigma at the mean rise speed U there.
//
//   oil_drop_bench [--particles 30,100,200] [--width 0.2] [--end 2.5] [--set key=value]...
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench_args.h"
#include "sim/bodies.h"
#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

using namespace mf;

struct Liquids {
  PhaseSpec water, oil;
  Real sigma, spacing, cfl, maxDt;
  std::string formulation;
};

Liquids shippedLiquids() {
  const Scene s = loadScene("water_oil");
  Liquids l;
  l.water = s.phases.at(size_t(s.phaseIndex("water")));
  l.oil = s.phases.at(size_t(s.phaseIndex("oil")));
  l.sigma = s.effect("interface_tension")->number("sigma");
  l.spacing = s.solver.particleSpacing;
  l.cfl = s.solver.cfl;
  l.maxDt = s.solver.maxDt;
  l.formulation = s.solver.density == DensityFormulation::Number ? "number" : "mass";
  return l;
}

constexpr Real kDepth = 0.25, kCentreHeight = 0.07;

std::string sceneText(const Liquids& l, Real R, Real width, Real end) {
  const Real c = 0.5 * width;
  return fmt::format(R"([scene]
name = "oil_drop"
end_time = {end}
frame_rate = 10
domain_min = [-0.01, -0.01, -0.01]
domain_max = [{wd}, 0.31, {wd}]
[solver]
pressure = "dfsph"
particle_spacing = {s}
density_formulation = "{f}"
cfl = {cfl}
max_dt = {dt}
[[phase]]
name = "water"
rest_density = {rw}
viscosity = {mw}
interface_colour = {cw}
[[phase]]
name = "oil"
rest_density = {ro}
viscosity = {mo}
interface_colour = {co}
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [{w}, 0.3, {w}]
[[fluid]]
phase = "oil"
shape = "sphere"
centre = [{c}, {y}, {c}]
radius = {R}
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [{w}, {depth}, {w}]
[[fluid.subtract]]
shape = "sphere"
centre = [{c}, {y}, {c}]
radius = {R}
[effects.gravity]
acceleration = [0.0, -9.81, 0.0]
[effects.pressure]
reference_density = {rw}
reference_level = {depth}
[effects.viscosity]
[effects.interface_tension]
sigma = {sigma}
)",
                     fmt::arg("end", end), fmt::arg("wd", width + 0.01), fmt::arg("s", l.spacing), fmt::arg("f", l.formulation),
                     fmt::arg("cfl", l.cfl), fmt::arg("dt", l.maxDt), fmt::arg("rw", l.water.restDensity), fmt::arg("mw", l.water.viscosity),
                     fmt::arg("cw", l.water.interfaceColour), fmt::arg("ro", l.oil.restDensity), fmt::arg("mo", l.oil.viscosity),
                     fmt::arg("co", l.oil.interfaceColour), fmt::arg("w", width), fmt::arg("c", c), fmt::arg("y", kCentreHeight),
                     fmt::arg("R", R), fmt::arg("depth", kDepth), fmt::arg("sigma", l.sigma));
}

void risingDrop(const Liquids& l, long particles, Real width, Real end, const std::vector<std::string>& sets) {
  // The ball that holds `particles` lattice sites has about that volume.
  const Real s = l.spacing, R = volumeRadius(size_t(particles), s);
  Simulation sim(parseScene(sceneText(l, R, width, end), "oil_drop.toml", sets));
  const int oil = sim.scene().phaseIndex("oil");
  size_t seeded = 0;
  for (int32_t p : sim.particles().phase) seeded += p == oil;
  const Real d = 2 * volumeRadius(seeded, s);  // the drop's diameter by volume
  fmt::print("oil drop of {} particles (d = {:.4f} m) in water, tank {} x 0.3 x {} m, {} particles in all\n", seeded, d, width, width,
             sim.particles().size());
  Real lastY = kCentreHeight, lastT = 0, roundSum = 0, speedSum = 0;
  int samples = 0;
  for (int k = 1; k * 0.1 <= end + 1e-9; ++k) {
    sim.advanceTo(k * 0.1);
    const ParticleSet& q = sim.particles();
    const std::vector<int32_t> phase(q.phase.begin(), q.phase.end());
    const FluidBodies b = findBodies(q.position.data(), phase.data(), q.size(), 1.5 * s);
    const FluidBody* drop = nullptr;
    int bodies = 0;
    for (const FluidBody& body : b.bodies)
      if (body.phase == oil) {
        ++bodies;
        if (!drop || body.size() > drop->size()) drop = &body;
      }
    if (!drop) break;
    const Real y = drop->centroid.y, speed = (y - lastY) / (sim.time() - lastT);
    const bool steady = y > kCentreHeight + d && drop->upper.y < kDepth - d;
    fmt::print("  t {:.1f} s: {} oil bodies, the largest {} particles, roundness {:.3f}, centroid y {:.4f} m, rising {:.3f} m/s{}\n",
               sim.time(), bodies, drop->size(), drop->roundness, y, speed, steady ? "  (steady rise)" : "");
    if (steady) roundSum += drop->roundness, speedSum += speed, ++samples;
    lastY = y, lastT = sim.time();
    if (drop->upper.y >= kDepth - 0.5 * d) break;  // at the surface
  }
  if (samples == 0) {
    fmt::print("  no steady rise seen by {:.1f} s\n", sim.time());
    return;
  }
  const Real U = speedSum / samples, drho = l.water.restDensity - l.oil.restDensity;
  fmt::print("  steady rise ({} samples): roundness {:.3f}, U {:.3f} m/s; Eo {:.2f}, Re {:.1f}, We {:.2f}\n", samples, roundSum / samples, U,
             drho * 9.81 * d * d / l.sigma, l.water.restDensity * U * d / l.water.viscosity, l.water.restDensity * U * U * d / l.sigma);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> sets;
  std::vector<long> counts = {30, 100, 200};
  Real width = 0.2, end = 2.5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--particles" && more) counts = bench::wholeList(a, argv[++i]);
    else if (a == "--width" && more) width = bench::number(a, argv[++i]);
    else if (a == "--end" && more) end = bench::number(a, argv[++i]);
    else if (a == "--set" && more) sets.push_back(argv[++i]);
    else {
      fmt::print(stderr, "usage: oil_drop_bench [--particles 30,100,200] [--width 0.2] [--end 2.5] [--set key=value]...\n");
      return 2;
    }
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  try {
    const Liquids l = shippedLiquids();
    for (const long n : counts) risingDrop(l, n, width, end, sets);
  } catch (const std::exception& e) {
    fmt::print(stderr, "oil_drop_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
