// effects_bench: what each effect costs on top of the SPH core, and how fast the paper's
// trapped-air and boiling scenes run.
//
// Part 1 (issue 3): a closed box of a random 50/50 mixture of two liquids (about 100 k
// particles by default) runs the core (gravity, pressure, viscosity) alone, then with one
// interaction effect added at a time. Printed per case: the whole step in ns per particle-step,
// the effect's own time (forces, advance and edits, from the simulation's stage timers) in ns
// per particle-step, and that time in units of the density pass, which is one neighbour pass
// (the density sum) and so the yardstick for "at most one extra neighbour pass".
// Part 2 (issue 4): configs/pour_glass.toml and configs/boiling.toml as committed, run for a
// stretch of simulated time from the start: steps and frames per second of wall time, particle
// counts, and the time of births and removals per step (the deciding effects, and applying
// the edits: compaction, appends and the new neighbour search).
//
//   effects_bench [--particles N] [--threads T] [--steps S] [--scene-seconds X] [--only 1|2]
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "bench_args.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A cube of n particles at a 1 cm spacing, water and oil drawn at random, in a closed box with
// 2 cm of headroom. `water` and `oil` are the extra [[phase]] keys the case's effect reads (the
// scene reader refuses material constants of effects that are not enabled), `effect` its tables.
std::string mixtureScene(long n, const std::string& water, const std::string& oil, const std::string& effect) {
  const int side = std::max(4, int(std::lround(std::cbrt(double(n)))));
  const double L = side * 0.01;
  return fmt::format(R"(
[scene]
name = "effects_bench"
end_time = 100.0
domain_min = [-0.05, -0.05, -0.05]
domain_max = [{d}, {d}, {d}]
[solver]
pressure = "wcsph"
particle_spacing = 0.01
density_formulation = "number"
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 400.0
viscosity = 0.1
{water}[[phase]]
name = "oil"
rest_density = 850.0
stiffness = 400.0
viscosity = 0.1
{oil}[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [{L}, {H}, {L}]
[[fluid]]
phases = ["water", "oil"]
fractions = [0.5, 0.5]
min = [0.0, 0.0, 0.0]
max = [{L}, {L}, {L}]
temperature = 20.0
[effects.gravity]
[effects.pressure]
[effects.viscosity]
{effect})",
                     fmt::arg("d", L + 0.1), fmt::arg("L", L), fmt::arg("H", L + 0.02), fmt::arg("water", water),
                     fmt::arg("oil", oil), fmt::arg("effect", effect));
}

struct Measured {
  size_t particles = 0;
  uint64_t steps = 0;
  double wall = 0, particleSteps = 0;
  mf::StageTimes times;  // differences over the measured steps
};

mf::StageTimes minus(const mf::StageTimes& a, const mf::StageTimes& b) {
  mf::StageTimes d = a;
  d.neighborSearch -= b.neighborSearch;
  d.density -= b.density;
  d.integrate -= b.integrate;
  d.edits -= b.edits;
  for (size_t k = 0; k < d.effect.size(); ++k) d.effect[k] -= k < b.effect.size() ? b.effect[k] : 0;
  return d;
}

// Steps until `steps` steps or `simSeconds` of simulated time have passed (whichever is given).
Measured measure(mf::Simulation& sim, uint64_t steps, double simSeconds) {
  Measured m;
  const mf::StageTimes before = sim.stageTimes();
  const uint64_t steps0 = sim.stepCount();
  const double t1 = sim.time() + simSeconds;
  const auto t0 = Clock::now();
  while (simSeconds > 0 ? sim.time() < t1 : sim.stepCount() - steps0 < steps) {
    sim.step(simSeconds > 0 ? t1 - sim.time() : 1.0);
    m.particleSteps += double(sim.particles().size());
  }
  m.wall = seconds(t0);
  m.steps = sim.stepCount() - steps0;
  m.particles = sim.particles().size();
  m.times = minus(sim.stageTimes(), before);
  return m;
}

double effectTime(const mf::Simulation& sim, const mf::StageTimes& t, const std::string& name) {
  for (size_t k = 0; k < sim.effects().size(); ++k)
    if (sim.effects()[k]->name() == name) return t.effect[k];
  return 0;
}

void partOne(long n, uint64_t steps) {
  struct Case {
    std::string effect, water, oil, table;
  };
  const std::vector<Case> cases = {
      {"", "", "", ""},
      {"interface_tension", "interface_colour = -0.5\n", "interface_colour = 0.5\n",
       "[effects.interface_tension]\nsigma = 0.05\n"},
      {"surface_tension", "surface_tension = 0.07\n", "surface_tension = 0.03\n", "[effects.surface_tension]\n"},
      {"heat_diffusion", "thermal_diffusivity = 1e-4\n", "thermal_diffusivity = 1e-4\n",
       "[effects.heat_diffusion]\n[[effects.heat_diffusion.source]]\nmin = [-0.05, -0.05, -0.05]\n"
       "max = [1.0, 0.02, 1.0]\ntemperature = 60.0\nrate = 1.0\n"},
      {"dye_diffusion", "dye_diffusivity = 1e-4\n", "dye_diffusivity = 1e-4\n", "[effects.dye_diffusion]\n"},
      {"thermal_expansion", "thermal_expansion = 2e-4\nreference_temperature = 20.0\n",
       "thermal_expansion = 7e-4\nreference_temperature = 20.0\n", "[effects.thermal_expansion]\n"},
  };
  fmt::print("Part 1: interaction effects on a water/oil mixture (number density, 1 cm spacing), {} steps each\n", steps);
  fmt::print("{:<20} {:>9} {:>12} {:>14} {:>14} {:>12}\n", "case", "particles", "ns/p-step", "effect ns/p-s",
             "density pass", "effect/pass");
  for (const Case& c : cases) {
    mf::Simulation sim(mf::parseScene(mixtureScene(n, c.water, c.oil, c.table), "<effects_bench>"));
    for (int k = 0; k < 3; ++k) sim.step(1.0);  // warm caches and allocations
    const Measured m = measure(sim, steps, 0);
    const double total = m.wall * 1e9 / m.particleSteps;
    const double pass = m.times.density * 1e9 / m.particleSteps;
    const double own = c.effect.empty() ? 0 : effectTime(sim, m.times, c.effect) * 1e9 / m.particleSteps;
    fmt::print("{:<20} {:>9} {:>12.0f} {:>14} {:>14.0f} {:>12}\n", c.effect.empty() ? "core" : "+ " + c.effect,
               m.particles, total, c.effect.empty() ? "-" : fmt::format("{:.0f}", own), pass,
               c.effect.empty() ? "-" : fmt::format("{:.2f}", own / pass));
    std::fflush(stdout);
  }
}

void partTwo(double sceneSeconds) {
  fmt::print("\nPart 2: the paper's scenes as committed, {} s of simulated time from the start\n", sceneSeconds);
  fmt::print("{:<11} {:>9} {:>7} {:>9} {:>9} {:>12} {:>14} {:>14}\n", "scene", "particles", "steps", "steps/s",
             "frames/s", "ns/p-step", "decide ms/step", "apply ms/step");
  for (const char* name : {"pour_glass", "boiling"}) {
    mf::Simulation sim(mf::loadScene(std::string(name)));
    const Measured m = measure(sim, 0, sceneSeconds);
    double decide = 0;
    for (const char* e : {"trapped_air", "emitter", "phase_change"}) decide += effectTime(sim, m.times, e);
    fmt::print("{:<11} {:>9} {:>7} {:>9.1f} {:>9.2f} {:>12.0f} {:>14.3f} {:>14.3f}\n", name, m.particles, m.steps,
               m.steps / m.wall, sceneSeconds * sim.scene().frameRate / m.wall, m.wall * 1e9 / m.particleSteps,
               decide * 1e3 / m.steps, m.times.edits * 1e3 / m.steps);
    std::string counts;
    for (const auto& e : sim.effects())
      for (const auto& [key, value] : e->statistics()) counts += fmt::format("{}{} {:g}", counts.empty() ? "" : ", ", key, value);
    if (!counts.empty()) fmt::print("            {}\n", counts);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  long particles = 100000, threads = 0;
  uint64_t steps = 20;
  double sceneSeconds = 0.5;
  int only = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      fmt::print(stderr, "{} needs a value\n", a);
      return 2;
    }
    if (a == "--particles") particles = mf::bench::whole(a, argv[++i]);
    else if (a == "--threads") threads = mf::bench::whole(a, argv[++i]);
    else if (a == "--steps") steps = size_t(mf::bench::whole(a, argv[++i]));
    else if (a == "--scene-seconds") sceneSeconds = mf::bench::number(a, argv[++i]);
    else if (a == "--only") only = int(mf::bench::whole(a, argv[++i]));
    else {
      fmt::print(stderr,
                 "usage: effects_bench [--particles N] [--threads T] [--steps S] [--scene-seconds X] [--only 1|2]\n");
      return 2;
    }
  }
  const size_t t = threads > 0 ? size_t(threads) : std::thread::hardware_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
  fmt::print("{} threads ({} hardware threads)\n", t, std::thread::hardware_concurrency());
  if (only != 2) partOne(particles, steps);
  if (only != 1) partTwo(sceneSeconds);
  return 0;
}
