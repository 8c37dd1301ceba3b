// Helpers for tests of simulations whose particles are born and die (test_air.cpp,
// test_boiling.cpp): the whole particle state as bytes, counts per phase, effect statistics.
#pragma once

#include <algorithm>
#include <string>

#include "sim/simulation.h"

namespace mf::test_util {

inline std::string stateBytes(Simulation& sim) {
  std::string bytes;
  sim.mutableParticles().forEachArray([&](const char*, const auto& v) {
    bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  });
  const double t = sim.time();
  bytes.append(reinterpret_cast<const char*>(&t), sizeof t);
  const uint64_t next = sim.nextId();
  bytes.append(reinterpret_cast<const char*>(&next), sizeof next);
  return bytes;
}

inline size_t countPhase(const Simulation& sim, const std::string& name) {
  const int ph = sim.scene().phaseIndex(name);
  const auto& p = sim.particles().phase;
  return size_t(std::count(p.begin(), p.end(), uint16_t(ph)));
}

inline double statistic(const Simulation& sim, const std::string& effect, const std::string& key) {
  for (const auto& e : sim.effects())
    if (e->name() == effect)
      for (const auto& [k, v] : e->statistics())
        if (k == key) return v;
  return -1;
}

}  // namespace mf::test_util
