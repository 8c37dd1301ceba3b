// Diagnostics for scenes with births and removals (trapped air, emitters, boiling), outside the
// test suite:
//   scene_stats frames DIR                      particles per phase (count, mean height) in each
//                                               DIR/particles/particles.NNNN.vdb, and the maxima
//   scene_stats run SCENE [END] [key=value...]  runs a scene, printing every 0.25 s each effect's
//                                               statistics, particles and mean temperature per
//                                               phase, the fastest particle and any outside the solids
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/solids.h"

namespace fs = std::filesystem;
using namespace mf;

namespace {

void frameStats(const char* dir) {
  size_t maxTotal = 0;
  std::map<std::string, size_t> maxPhase;
  for (int f = 0;; ++f) {
    const fs::path file = fs::path(dir) / "particles" / fmt::format("particles.{:04d}.vdb", f);
    if (!fs::exists(file)) break;
    const ParticleFrame fr = readParticleFrame(file.string());
    std::map<std::string, size_t> count;
    std::map<std::string, Real> meanY;
    for (size_t k = 0; k < fr.size(); ++k) {
      const std::string& name = fr.info.phaseNames.at(size_t(fr.phase[k]));
      ++count[name];
      meanY[name] += fr.position[k].y;
    }
    std::string line = fmt::format("frame {:3d} t {:.3f} s: {:5d} particles", f, fr.info.time, fr.size());
    for (const auto& [name, n] : count) {
      line += fmt::format(", {} {} (mean y {:.4f})", name, n, meanY[name] / Real(n));
      maxPhase[name] = std::max(maxPhase[name], n);
    }
    maxTotal = std::max(maxTotal, fr.size());
    fmt::print("{}\n", line);
  }
  fmt::print("at most {} particles in a frame", maxTotal);
  for (const auto& [name, n] : maxPhase) fmt::print(", {} at most {}", name, n);
  fmt::print("\n");
}

void runScene(const char* name, Real endTime, const std::vector<std::string>& sets) {
  Simulation sim(loadScene(name, sets));
  const Real end = endTime > 0 ? endTime : sim.scene().endTime;
  for (Real t = 0.25; t <= end + 1e-9; t += 0.25) {
    sim.advanceTo(t);
    std::string line = fmt::format("t {:.2f} s, {} steps:", t, sim.stepCount());
    for (size_t p = 0; p < sim.scene().phases.size(); ++p) {
      size_t n = 0;
      Real T = 0, y = 0;
      for (size_t i = 0; i < sim.particles().size(); ++i)
        if (sim.particles().phase[i] == p) {
          ++n;
          y += sim.particles().position[i].y;
          if (sim.particles().has(Attribute::Temperature)) T += sim.particles().temperature[i];
        }
      line += fmt::format(" {} {} (T {:.1f}, y {:.4f})", sim.scene().phases[p].name, n, n ? T / Real(n) : 0.0, n ? y / Real(n) : 0.0);
    }
    for (const auto& e : sim.effects())
      for (const auto& [k, v] : e->statistics()) line += fmt::format(" {}.{}={:g}", e->name(), k, v);
    Real vmax = 0, ymax = -1e9;
    for (size_t i = 0; i < sim.particles().size(); ++i) {
      vmax = std::max(vmax, length(sim.particles().velocity[i]));
      ymax = std::max(ymax, sim.particles().position[i].y);
    }
    line += fmt::format(" vmax={:.2f} ymax={:.3f}", vmax, ymax);
    size_t outside = 0, aboveRimOutside = 0;
    for (size_t i = 0; i < sim.particles().size(); ++i) {
      bool in = sim.scene().solids.empty();
      for (const SolidSpec& so : sim.scene().solids) in |= insideFluidRegion(so, sim.particles().position[i], 0.5 * sim.particleSpacing());
      outside += !in;
      aboveRimOutside += !in && sim.particles().position[i].y > 0.1;
    }
    line += fmt::format(" outside_solids={} (of which above 0.1 m: {}) wall_clamps={} out_of_domain={}", outside, aboveRimOutside,
                        sim.counters().wallClamps, sim.counters().removedOutOfDomain);
    fmt::print("{}\n", line);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 3 && std::strcmp(argv[1], "frames") == 0) {
      frameStats(argv[2]);
      return 0;
    }
    if (argc >= 3 && std::strcmp(argv[1], "run") == 0) {
      Real end = 0;
      int k = 3;
      if (argc > 3 && std::strchr(argv[3], '=') == nullptr) end = std::atof(argv[k++]);
      std::vector<std::string> sets(argv + k, argv + argc);
      runScene(argv[2], end, sets);
      return 0;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "scene_stats: {}\n", e.what());
    return 1;
  }
  fmt::print(stderr, "usage: scene_stats frames DIR | scene_stats run SCENE [END] [key=value...]\n");
  return 2;
}
