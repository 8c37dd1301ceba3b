// Diagnostics for scenes with births and removals (trapped air, emitters, boiling), outside the
// test suite:
//   scene_stats frames DIR                      particles per phase (count, mean height) in each
//                                               DIR/particles/particles.NNNN.vdb, and the maxima
//   scene_stats run SCENE [END] [every=DT] [slice] [key=value...]
//                                               runs a scene, printing every DT s (0.25) each
//                                               effect's statistics; per phase the particles, mean
//                                               and highest temperature, mean and highest height;
//                                               the total mass; the fastest particle now (vmax) and
//                                               over the interval, every step (vmax_step, with its
//                                               phase); and any particles outside the solids.
//                                               slice: an x-y slice through z = 0 (0..0.1 m high,
//                                               |x| < 5.5 cm), one character per spacing
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/solids.h"
#include "bench_args.h"

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

// An x-y slice one spacing thick through z = 0, one character per spacing: the phase's first
// letter (capital where it holds more than one particle), '.' for none.
void printSlice(const Simulation& sim, Real ylo, Real yhi, Real half) {
  const ParticleSet& ps = sim.particles();
  const Real s = sim.particleSpacing();
  const int nx = int(std::ceil(2 * half / s)), ny = int(std::ceil((yhi - ylo) / s));
  std::vector<int> count(size_t(nx * ny), 0), phase(size_t(nx * ny), -1);
  for (size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.position[i];
    if (std::abs(x.z) > 0.5 * s) continue;
    const int cx = int(std::floor((x.x + half) / s)), cy = int(std::floor((x.y - ylo) / s));
    if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) continue;
    const size_t c = size_t(cy * nx + cx);
    // vapour-like phases (not the first) win over the liquid in a shared cell
    if (phase[c] < 0 || int(ps.phase[i]) > phase[c]) phase[c] = ps.phase[i];
    ++count[c];
  }
  for (int cy = ny - 1; cy >= 0; --cy) {
    std::string row = fmt::format("  {:+.3f} |", ylo + (cy + 0.5) * s);
    for (int cx = 0; cx < nx; ++cx) {
      const size_t c = size_t(cy * nx + cx);
      if (phase[c] < 0) row += '.';
      else {
        const char ch = sim.scene().phases[size_t(phase[c])].name[0];
        row += count[c] > 1 ? char(std::toupper(ch)) : ch;
      }
    }
    fmt::print("{}|\n", row);
  }
}

void runScene(const char* name, Real endTime, Real every, const std::vector<std::string>& sets, bool slice) {
  Simulation sim(loadScene(name, sets));
  const Real end = endTime > 0 ? endTime : sim.scene().endTime;
  Real vmaxStep = 0;
  int vmaxPhase = -1;
  auto track = [&](const Simulation& s) {
    for (size_t i = 0; i < s.particles().size(); ++i) {
      const Real v = length(s.particles().velocity[i]);
      if (v > vmaxStep) {
        vmaxStep = v;
        vmaxPhase = s.particles().phase[i];
      }
    }
  };
  for (int k = 1; Real(k) * every <= end + 1e-9; ++k) {
    const Real t = Real(k) * every;
    vmaxStep = 0;
    vmaxPhase = -1;
    sim.advanceTo(t, track);
    const ParticleSet& ps = sim.particles();
    const bool hasT = ps.has(Attribute::Temperature);
    std::string line = fmt::format("t {:.2f} s, {} steps:", t, sim.stepCount());
    Real mass = 0;
    for (size_t i = 0; i < ps.size(); ++i) mass += ps.mass[i];
    for (size_t p = 0; p < sim.scene().phases.size(); ++p) {
      size_t n = 0;
      Real T = 0, y = 0, Tmax = -1e9, ymax = -1e9;
      for (size_t i = 0; i < ps.size(); ++i)
        if (ps.phase[i] == p) {
          ++n;
          y += ps.position[i].y;
          ymax = std::max(ymax, ps.position[i].y);
          if (hasT) {
            T += ps.temperature[i];
            Tmax = std::max(Tmax, ps.temperature[i]);
          }
        }
      const std::string temperature =
          hasT && n ? fmt::format("T {:.2f} max {:.1f}, ", T / Real(n), Tmax) : std::string();  // none without temperatures
      line += fmt::format(" {} {} ({}y {:.4f} max {:.4f})", sim.scene().phases[p].name, n, temperature,
                          n ? y / Real(n) : 0.0, n ? ymax : 0.0);
    }
    line += fmt::format(" mass={:.6g}", mass);
    for (const auto& e : sim.effects())
      for (const auto& [k2, v] : e->statistics()) line += fmt::format(" {}.{}={:g}", e->name(), k2, v);
    Real vmax = 0, ymax = -1e9;
    for (size_t i = 0; i < ps.size(); ++i) {
      vmax = std::max(vmax, length(ps.velocity[i]));
      ymax = std::max(ymax, ps.position[i].y);
    }
    line += fmt::format(" vmax={:.2f} vmax_step={:.2f} ({}) ymax={:.3f}", vmax, vmaxStep,
                        vmaxPhase >= 0 ? sim.scene().phases[size_t(vmaxPhase)].name : "-", ymax);
    size_t outside = 0, aboveRimOutside = 0;
    for (size_t i = 0; i < ps.size(); ++i) {
      bool in = sim.scene().solids.empty();
      for (const SolidSpec& so : sim.scene().solids) in |= insideFluidRegion(so, ps.position[i], 0.5 * sim.particleSpacing());
      outside += !in;
      aboveRimOutside += !in && ps.position[i].y > 0.1;
    }
    line += fmt::format(" outside_solids={} (of which above 0.1 m: {}) wall_clamps={} out_of_domain={}", outside, aboveRimOutside,
                        sim.counters().wallClamps, sim.counters().removedOutOfDomain);
    fmt::print("{}\n", line);
    if (slice) printSlice(sim, 0.0, 0.1, 0.055);
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
      if (argc > 3 && std::strchr(argv[3], '=') == nullptr) end = bench::number("END", argv[k++]);
      Real every = 0.25;
      if (k < argc && std::strncmp(argv[k], "every=", 6) == 0) every = bench::number("every", argv[k++] + 6);
      if (!(every > 0)) throw std::runtime_error("every= must be positive");
      bool slice = false;
      if (k < argc && std::strcmp(argv[k], "slice") == 0) {
        slice = true;
        ++k;
      }
      std::vector<std::string> sets(argv + k, argv + argc);
      runScene(argv[2], end, every, sets, slice);
      return 0;
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "scene_stats: {}\n", e.what());
    return 1;
  }
  fmt::print(stderr, "usage: scene_stats frames DIR | scene_stats run SCENE [END] [every=DT] [slice] [key=value...]\n");
  return 2;
}
