// bubble_bench: a ball of gas starting up from rest in still water, against a sphere's
// (rho_l - rho_g) / (rho_g + rho_l / 2) g with its added mass (docs/pressure_solvers.md, "Light
// phases: the added density"). For each gas density, added density and radius (one particle at
// 0.0055 m, 81 at 0.025 m; bubbleInTankScene, sim/diagnostics.h) it prints the gas's mean upward
// speed after one step of 0.5 ms and after six (3 ms), each divided by the time reached (less
// where the watchdog retried a step), or where the watchdog stopped the run.
//
//   bubble_bench [--gas 100,1.2] [--added 0,200,300,500] [--radii 0.0055,0.025] [--threads 2]
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <exception>
#include <string>
#include <vector>

#include "bench_args.h"
#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

int main(int argc, char** argv) {
  using namespace mf;
  std::vector<std::string> gases{"100", "1.2"}, added{"0", "200", "300", "500"}, radii{"0.0055", "0.025"};
  long threads = 2;
  for (int a = 1; a < argc; ++a) {
    const std::string flag = argv[a];
    if (a + 1 >= argc) {
      fmt::print(stderr, "usage: bubble_bench [--gas 100,1.2] [--added 0,200,300,500] [--radii 0.0055,0.025] [--threads 2]\n");
      return 2;
    }
    const std::string value = argv[++a];
    if (flag == "--gas") gases = bench::splitCommas(value);
    else if (flag == "--added") added = bench::splitCommas(value);
    else if (flag == "--radii") radii = bench::splitCommas(value);
    else if (flag == "--threads") threads = bench::whole("--threads", value);
    else {
      fmt::print(stderr, "bubble_bench: unknown flag {}\n", flag);
      return 2;
    }
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads > 0 ? threads : 1));
  constexpr Real g = 9.81, water = 1000, step = 0.0005;
  fmt::print("{:>10} {:>8} {:>8} {:>6} {:>10} {:>10} {:>10}\n", "gas kg/m3", "added", "radius", "gas", "1 step", "6 steps", "sphere");
  for (const std::string& gs : gases)
    for (const std::string& as : added)
      for (const std::string& rs : radii) {
        const Real rho = bench::number("--gas", gs), add = bench::number("--added", as), R = bench::number("--radii", rs);
        const Real sphere = (water - rho) / (rho + water / 2);
        std::string row = fmt::format("{:>10} {:>8} {:>8} ", gs, as, rs);
        try {
          Simulation sim(parseScene(bubbleInTankScene(rho, add, R), "bubble.toml"));
          const int gas = sim.scene().phaseIndex("air");
          std::string cells;
          size_t count = 0;
          for (int k = 1; k <= 6; ++k) {
            sim.step(step);
            if (k != 1 && k != 6) continue;
            Real vy = 0;
            count = 0;
            for (size_t i = 0; i < sim.particles().size(); ++i)
              if (sim.particles().phase[i] == gas) vy += sim.particles().velocity[i].y, ++count;
            cells += fmt::format(" {:>9.2f}g", vy / Real(count) / sim.time() / g);
          }
          row += fmt::format("{:>6}{} {:>9.2f}g", count, cells, sphere);
        } catch (const std::exception& e) {
          row += fmt::format("stopped: {}", std::string(e.what()).substr(0, 120));
        }
        fmt::print("{}\n", row);
      }
}
