// scene_solver_bench: every shipped scene on both pressure solvers, side by side in one run.
// For each scene and solver it prints the particles (start and end), the steps, the wall time
// per simulated second, the retries, the wall clamps, the peak compression and the ratio of the
// two solvers' wall times, the table issue 21 asks for ("each shipped scene at least 3x faster per
// simulated second than today's WCSPH at the same spacing").
//
//   scene_solver_bench [--end T] [--scenes a,b,...] [--solvers wcsph,dfsph] [--threads N] [--set key=value]...
// --end sets scene.end_time (default 1 s, shorter than the shipped runs: the cost per simulated
// second is what is compared, and it is measured over the same interval for both solvers).
// A run the watchdog stops is reported with its message; the bench goes on.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

struct Result {
  size_t start = 0, end = 0;
  double wall = 0, simulated = 0;
  mf::SimulationCounters counters;
  std::string stopped;
};

// The scenes that ship on DFSPH carry no stiffness. Their WCSPH baseline is the scene as it
// shipped on WCSPH: the pressure effect, its phases' stiffness, the gradient correction, and the
// lamp's interface tension.
std::vector<std::string> wcsphBaseline(const std::string& scene) {
  auto stiffness = [](std::initializer_list<const char*> phases, double k) {
    std::vector<std::string> v = {"effects.pressure.enabled=true"};
    for (const char* p : phases) v.push_back(fmt::format("phase.{}.stiffness={}", p, k));
    return v;
  };
  if (scene == "dam_break") return stiffness({"water"}, 400);
  if (scene == "two_fluids_mixed") return stiffness({"light", "heavy"}, 200);
  if (scene == "lava_lamp") {
    auto v = stiffness({"fluid", "wax"}, 500);
    v.insert(v.end(), {"effects.pressure.gradient_correction=1", "effects.interface_tension.sigma=8"});
    return v;
  }
  if (scene == "water_oil") {
    auto v = stiffness({"water", "oil"}, 200);
    v.push_back("effects.pressure.gradient_correction=1");
    return v;
  }
  if (scene == "boiling") return stiffness({"water", "vapour", "flame"}, 400);
  if (scene == "diffusion") return stiffness({"liquid"}, 100);
  if (scene == "pour_glass") {
    auto v = stiffness({"water", "air"}, 500);
    v.push_back("effects.trapped_air.generation_threshold=0.6");
    return v;
  }
  return {};
}

Result run(const std::string& name, const std::string& solver, double end, const std::vector<std::string>& sets) {
  std::vector<std::string> all = {fmt::format("solver.pressure=\"{}\"", solver), fmt::format("scene.end_time={}", end)};
  if (solver == "wcsph") {
    const auto baseline = wcsphBaseline(name);
    all.insert(all.end(), baseline.begin(), baseline.end());
  }
  all.insert(all.end(), sets.begin(), sets.end());
  Result r;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    mf::Simulation sim(mf::loadScene(name, all));
    r.start = sim.particles().size();
    try {
      sim.advanceTo(end);
    } catch (const std::exception& e) {
      r.stopped = e.what();
    }
    r.end = sim.particles().size();
    r.simulated = sim.time();
    r.counters = sim.counters();
  } catch (const std::exception& e) {
    r.stopped = e.what();
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"dam_break", "two_fluids_mixed", "water_oil", "diffusion",
                                     "lava_lamp", "pour_glass", "boiling"};
  std::vector<std::string> sets, solvers = {"wcsph", "dfsph"};
  double end = 1.0;
  int threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      fmt::print(stderr, "{} needs a value\n", a);
      return 2;
    }
    if (a == "--end") end = mf::bench::number(a, argv[++i]);
    else if (a == "--scenes") scenes = mf::bench::splitCommas(argv[++i]);
    else if (a == "--solvers") solvers = mf::bench::splitCommas(argv[++i]);
    else if (a == "--threads") threads = int(mf::bench::whole(a, argv[++i]));
    else if (a == "--set") sets.push_back(argv[++i]);
    else {
      fmt::print(stderr, "usage: scene_solver_bench [--end T] [--scenes a,b] [--solvers wcsph,dfsph] [--threads N] [--set key=value]...\n");
      return 2;
    }
  }
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(threads));
  fmt::print("shipped scenes to t = {} s on both solvers (wall s per simulated s; compression = largest (rho - rho0)/rho0)\n", end);
  fmt::print("{:<17} {:<6} {:>9} {:>7} {:>8} {:>8} {:>7} {:>7} {:>8} {:>11}\n", "scene", "solver", "particles", "steps",
             "wall/s", "iter/st", "retries", "clamps", "compr.", "WCSPH/DFSPH");
  for (const std::string& name : scenes) {
    double wallPerSecond[2] = {0, 0};
    for (int s = 0; s < 2; ++s) {
      const std::string solver = s == 0 ? "wcsph" : "dfsph";
      if (std::find(solvers.begin(), solvers.end(), solver) == solvers.end()) continue;
      const Result r = run(name, solver, end, sets);
      const mf::SimulationCounters& c = r.counters;
      wallPerSecond[s] = r.simulated > 0 ? r.wall / r.simulated : 0;
      const double iterations = c.steps ? double(c.pressureIterations + c.divergenceIterations) / double(c.steps) : 0;
      const std::string ratio = s == 1 && wallPerSecond[0] > 0 && wallPerSecond[1] > 0 && r.stopped.empty()
                                    ? fmt::format("{:.2f}x", wallPerSecond[0] / wallPerSecond[1]) : "";
      fmt::print("{:<17} {:<6} {:>4}-{:<4} {:>7} {:>8.1f} {:>8.1f} {:>7} {:>7} {:>7.1f}% {:>11}\n", name, solver, r.start,
                 r.end, c.steps, wallPerSecond[s], iterations, c.retries, c.wallClamps, 100 * c.maxDensityError, ratio);
      if (!r.stopped.empty()) fmt::print("  stopped at t = {:.4g} s: {}\n", r.simulated, r.stopped);
      std::fflush(stdout);
    }
  }
  return 0;
}
