// sim_bench: cost of the SPH core on a dam break at several sizes and thread counts.
// Prints ns per particle-step (wall time x threads-independent: wall ns / particles / steps),
// steps per second, mean neighbour count, the implicit solves' iterations per step (DFSPH: both
// solves and the compression passes' iterations), the split by stage ("press." is WCSPH's pressure
// force or DFSPH's solves) and the process's peak memory.
//
//   sim_bench [--particles 10000,100000,1000000] [--threads 1,2] [--seconds 3 | --steps N]
//             [--set key=value]...
// Sizes run in increasing order (peak memory is the process's high-water mark).
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <chrono>
#include <thread>
#include <cmath>
#include <string>
#include <vector>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "bench_args.h"

namespace {

double peakMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// The Martin & Moyce dam break (configs/dam_break.toml) with the spacing chosen so that the
// a x 2a x a column holds about `particles` particles.
mf::Scene damBreak(long particles, const std::vector<std::string>& sets) {
  const double a = 0.05715;
  const int n = std::max(4, int(std::lround(std::cbrt(particles / 2.0))));
  std::vector<std::string> all = {fmt::format("solver.particle_spacing={:.9g}", a / n * (1 - 1e-9))};
  all.insert(all.end(), sets.begin(), sets.end());
  return mf::loadScene("dam_break", all);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> sizes = {10000, 100000, 1000000}, threads = {1, 2};
  double seconds = 3;
  long fixedSteps = 0;  // --steps: exactly this many measured steps (the same flow for every setting)
  std::vector<std::string> sets;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      fmt::print(stderr, "{} needs a value\n", a);
      return 2;
    }
    if (a == "--particles") sizes = mf::bench::wholeList(a, argv[++i]);
    else if (a == "--threads") threads = mf::bench::wholeList(a, argv[++i]);
    else if (a == "--seconds") seconds = mf::bench::number(a, argv[++i]);
    else if (a == "--steps") fixedSteps = mf::bench::whole(a, argv[++i]);
    else if (a == "--set") sets.push_back(argv[++i]);
    else {
      fmt::print(stderr, "usage: sim_bench [--particles N,N] [--threads T,T] [--seconds S | --steps N] [--set key=value]\n");
      return 2;
    }
  }
  fmt::print("dam break (configs/dam_break.toml, gravity + pressure + viscosity), {} hardware threads\n",
             std::thread::hardware_concurrency());
  fmt::print("{:>9} {:>7} {:>6} {:>9} {:>10} {:>8} {:>7} | {:>7} {:>7} {:>7} {:>7} {:>7} | {:>9}\n", "particles", "threads",
             "steps", "ns/p-step", "steps/s", "nbrs", "it/step", "search", "density", "press.", "visc.", "integr.", "peak MiB");
  for (long size : sizes) {
    const mf::Scene scene = damBreak(size, sets);
    for (long t : threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(t));
      mf::Simulation sim(scene);
      for (int k = 0; k < 3; ++k) sim.step(1.0);  // warm caches and allocations
      const mf::StageTimes before = sim.stageTimes();
      const uint64_t steps0 = sim.stepCount();
      const uint64_t iterations0 = sim.counters().pressureIterations + sim.counters().divergenceIterations;
      double particleSteps = 0;
      const auto t0 = std::chrono::steady_clock::now();
      double elapsed = 0;
      while (fixedSteps > 0 ? sim.stepCount() - steps0 < uint64_t(fixedSteps) : (elapsed < seconds || sim.stepCount() - steps0 < 3)) {
        sim.step(1.0);
        particleSteps += double(sim.particles().size());
        elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      const uint64_t steps = sim.stepCount() - steps0;
      const mf::StageTimes& after = sim.stageTimes();
      auto share = [&](double a, double b) { return fmt::format("{:>6.1f}%", 100 * (a - b) / elapsed); };
      double pressure = after.pressure, viscosity = 0, pressure0 = before.pressure, viscosity0 = 0;
      for (size_t k = 0; k < sim.effects().size(); ++k) {
        const std::string name = sim.effects()[k]->name();
        const double b = k < before.effect.size() ? before.effect[k] : 0;
        if (name == "pressure") pressure += after.effect[k], pressure0 += b;
        if (name == "viscosity") viscosity = after.effect[k], viscosity0 = b;
      }
      const uint64_t iterations = sim.counters().pressureIterations + sim.counters().divergenceIterations - iterations0;
      fmt::print("{:>9} {:>7} {:>6} {:>9.0f} {:>10.1f} {:>8.1f} {:>7.1f} | {} {} {} {} {} | {:>9.0f}\n", sim.particles().size(), t,
                 steps, elapsed * 1e9 / particleSteps, steps / elapsed,
                 double(sim.fluidNeighbors().totalPairs()) / double(sim.particles().size()), double(iterations) / double(steps),
                 share(after.neighborSearch, before.neighborSearch), share(after.density, before.density),
                 share(pressure, pressure0), share(viscosity, viscosity0), share(after.integrate, before.integrate),
                 peakMiB());
      std::fflush(stdout);
    }
  }
  return 0;
}
