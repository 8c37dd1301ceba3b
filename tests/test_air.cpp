// Particles that are born and die (Mueller et al. 2005, section 5): emitters and sinks, trapped
// air (generation, deletion, buoyancy); ids, caps, determinism and checkpoints with a changing
// particle count. Phase change: test_boiling.cpp.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "particle_test_util.h"
#include "sim/diagnostics.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/solids.h"

namespace fs = std::filesystem;

namespace {

using namespace mf;
using namespace mf::test_util;

// A tank with a pool of water (spacing 1 cm) and an air phase; `extra` adds tables.
std::string poolScene(const std::string& extra, Real poolHeight = 0.08, const std::string& trappedAir = "") {
  return fmt::format(R"(
[scene]
name = "pool"
end_time = 1.0
domain_min = [-0.05, -0.05, -0.05]
domain_max = [0.21, 0.4, 0.21]
[solver]
pressure = "wcsph"  # the solver the rule was measured on: on DFSPH the jet below traps 9 air particles, not 10 (docs/pressure_solvers.md)
particle_spacing = 0.01
density_formulation = "number"
max_dt = 0.002
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 400.0
viscosity = 0.2
[[phase]]
name = "air"
rest_density = 100.0
stiffness = 1000.0  # c = 32 m/s; at 400 an air particle born under the 2.5 m/s jet was crushed by 50 %
viscosity = 0.02
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.16, 0.35, 0.16]
open_top = true
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.16, {pool}, 0.16]
[effects.gravity]
[effects.pressure]
[effects.viscosity]
[effects.trapped_air]
liquid = "water"
air = "air"
{trapped}
{extra}
)",
                     fmt::arg("pool", poolHeight), fmt::arg("extra", extra), fmt::arg("trapped", trappedAir));
}

const char* kJet = R"(
[effects.emitter]
[[effects.emitter.disc]]
phase = "water"
centre = [0.08, 0.2, 0.08]
radius = 0.015
velocity = [0.0, -2.5, 0.0]
end = 0.1
)";

// ---- emitters, sinks and ids ---------------------------------------------------------------

TEST(Emitter, IdsStayUniqueThroughThousandsOfBirthsAndRemovals) {
  // A stream falls from a nozzle into a sink: every particle is born and removed again.
  const std::string text = R"(
[scene]
name = "stream"
end_time = 1.0
domain_min = [-0.2, -0.2, -0.2]
domain_max = [0.2, 0.4, 0.2]
[solver]
particle_spacing = 0.01
max_dt = 0.002
[[phase]]
name = "water"
rest_density = 1000.0
viscosity = 0.1
[[fluid]]
phase = "water"
min = [-0.03, 0.3, -0.03]
max = [0.03, 0.36, 0.03]
[effects.gravity]
[effects.viscosity]
[effects.emitter]
[[effects.emitter.disc]]
phase = "water"
centre = [0.0, 0.2, 0.0]
radius = 0.02
velocity = [0.0, -2.0, 0.0]
end = 0.8
[[effects.emitter.sink]]
min = [-0.2, -0.2, -0.2]
max = [0.2, 0.05, 0.2]
)";
  Simulation sim(parseScene(text, "stream.toml"));
  const uint64_t seeded = sim.particles().size();
  std::set<uint64_t> everSeen(sim.particles().id.begin(), sim.particles().id.end());
  uint64_t maxCount = 0, steps = 0;
  bool unique = true, fresh = true;
  sim.advanceTo(1.0, [&](const Simulation& s) {
    ++steps;
    const auto& id = s.particles().id;
    std::set<uint64_t> now(id.begin(), id.end());
    unique &= now.size() == id.size();
    for (uint64_t i : id)
      if (!everSeen.count(i)) {
        fresh &= i >= seeded && i < s.nextId();  // a new id comes from the counter, never an old one
        everSeen.insert(i);
      }
    maxCount = std::max<uint64_t>(maxCount, id.size());
  });
  const double perLayer = statistic(sim, "emitter", "nozzle0.per_layer");
  const double emitted = statistic(sim, "emitter", "nozzle0.emitted");
  fmt::print("stream: {} per layer, {} emitted, {} removed by the sink, {} alive, {} steps, at most {} at once\n", perLayer,
             emitted, sim.counters().removedByEffects, sim.particles().size(), steps, maxCount);
  EXPECT_TRUE(unique);
  EXPECT_TRUE(fresh);
  // Layers leave every s/|v| = 5 ms from t = 0 to 0.8 s inclusive: 161 layers exactly.
  EXPECT_EQ(perLayer, 13);  // lattice points of spacing 1 cm within 2 cm: 1 + 4 + 4 + 4
  EXPECT_EQ(emitted, 161 * perLayer);
  EXPECT_EQ(sim.counters().born, uint64_t(emitted));
  EXPECT_GT(sim.counters().removedByEffects, 2000u);
  // Particle bookkeeping: alive = seeded + born - removed.
  EXPECT_EQ(sim.particles().size() + sim.counters().removedByEffects + sim.counters().removedOutOfDomain,
            seeded + sim.counters().born);
  EXPECT_EQ(sim.nextId(), seeded + sim.counters().born);
  EXPECT_EQ(everSeen.size(), sim.nextId());
}

TEST(Emitter, BadEntriesNameFileLineAndKey) {
  const std::string base = poolScene(R"(
[effects.emitter]
[[effects.emitter.disc]]
phase = "water"
centre = [0.08, 0.2, 0.08]
radius = 0.015
velocity = [0.0, 0.0, 0.0]
[[effects.emitter.sink]]
min = [0.0, 0.0, 0.0]
max = [0.1, -0.1, 0.1]
)");
  try {
    parseScene(base, "bad.toml");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("key 'effects.emitter.disc[0].velocity': must not be zero"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'effects.emitter.sink[0].max': must be greater than min"), std::string::npos) << m;
    EXPECT_NE(m.find("bad.toml:"), std::string::npos) << m;
  }
  try {
    parseScene(poolScene("", 0.08, "distance = 3.0\nmax_air = -1"), "bad2.toml");
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("key 'effects.trapped_air.distance': value 3 outside the allowed range [0.3, 1.5]"), std::string::npos) << m;
    EXPECT_NE(m.find("key 'effects.trapped_air.max_air': value -1 outside the allowed range"), std::string::npos) << m;
  }
}

// ---- trapped air -----------------------------------------------------------------------------

TEST(TrappedAir, StillPoolGeneratesNoAir) {
  Simulation sim(parseScene(poolScene(""), "still.toml"));
  sim.advanceTo(0.4);
  fmt::print("still pool: {} particles, generated {}\n", sim.particles().size(), statistic(sim, "trapped_air", "generated"));
  EXPECT_EQ(statistic(sim, "trapped_air", "generated"), 0);
  EXPECT_EQ(countPhase(sim, "air"), 0u);
}

TEST(TrappedAir, PlungingJetTrapsAirOnlyBelowTheSurface) {
  Simulation sim(parseScene(poolScene(kJet), "jet.toml"));
  const int air = sim.scene().phaseIndex("air"), water = sim.scene().phaseIndex("water");
  uint64_t known = sim.nextId(), born = 0, notCovered = 0, bornBeforeImpact = 0;
  Real highest = -1, surfaceAtEnd = 0, impact = -1;
  sim.advanceTo(0.5, [&](const Simulation& s) {
    const ParticleSet& ps = s.particles();
    // The still surface (8 cm) raised by the water emitted so far, spread over the tank.
    const Real emitted = statistic(s, "emitter", "nozzle0.emitted");
    const Real surface = 0.08 + emitted * 1e-6 / (0.16 * 0.16);
    surfaceAtEnd = surface;
    Real lowestJet = 1;
    for (size_t i = 0; i < ps.size(); ++i)
      if (ps.phase[i] == water && ps.id[i] >= 2048) lowestJet = std::min(lowestJet, ps.position[i].y);
    if (impact < 0 && lowestJet < surface + 0.01) impact = s.time();
    for (size_t i = 0; i < ps.size(); ++i) {
      if (ps.id[i] < known || ps.phase[i] != air) continue;
      ++born;
      if (impact < 0) ++bornBeforeImpact;
      highest = std::max(highest, ps.position[i].y - surface);
      // Below the surface where it is: some water above it within one spacing horizontally.
      bool covered = false;
      for (size_t j = 0; j < ps.size() && !covered; ++j) {
        const Vec3 d = ps.position[j] - ps.position[i];
        covered = ps.phase[j] == water && d.y > 0 && d.x * d.x + d.z * d.z <= 1e-4;
      }
      notCovered += !covered;
    }
    known = s.nextId();
  });
  fmt::print("jet: impact at t = {:.3f} s; {} air particles born ({} before the impact), the highest {:.4f} m above the mean "
             "surface ({:.4f} m at the end), {} without water above them; {} alive at the end; deleted isolated {}, at the "
             "surface {}\n",
             impact, born, bornBeforeImpact, highest, surfaceAtEnd, notCovered, countPhase(sim, "air"),
             statistic(sim, "trapped_air", "deleted_isolated"), statistic(sim, "trapped_air", "deleted_at_surface"));
  EXPECT_GT(born, 10u);
  EXPECT_EQ(bornBeforeImpact, 0u);  // none under the falling jet in the open
  EXPECT_EQ(notCovered, 0u);        // every one under water
  // Crater rims and the crown stand above the mean level, but not by much: 3 spacings.
  EXPECT_LT(highest, 0.03);
}

// A pool with a ball of air (water removed where the ball is).
Simulation poolWithBubble(const std::string& extra, Vec3 centre, Real radius) {
  const std::string text = poolScene(extra + fmt::format(R"(
[[fluid]]
phase = "air"
shape = "sphere"
centre = [{}, {}, {}]
radius = {}
)",
                                                         centre.x, centre.y, centre.z, radius),
                                     0.2);
  Simulation sim(parseScene(text, "bubble.toml"));
  ParticleSet& ps = sim.mutableParticles();
  const int water = sim.scene().phaseIndex("water");
  std::vector<uint8_t> remove(ps.size(), 0);
  for (size_t i = 0; i < ps.size(); ++i)
    remove[i] = ps.phase[i] == water && length(ps.position[i] - centre) < radius + 0.004;
  ps.removeFlagged(remove);
  sim.refresh();
  return sim;
}

TEST(TrappedAir, IsolatedAirIsRemovedWithinAFewSteps) {
  Simulation sim(parseScene(poolScene(R"(
[[fluid]]
phase = "air"
shape = "sphere"
centre = [0.08, 0.3, 0.08]
radius = 0.006
)"),
                            "lonely.toml"));
  ASSERT_EQ(countPhase(sim, "air"), 1u);
  int steps = 0;
  while (countPhase(sim, "air") > 0 && steps < 10) {
    sim.step(1.0);
    ++steps;
  }
  fmt::print("isolated air particle removed after {} step(s)\n", steps);
  EXPECT_LE(steps, 3);
  EXPECT_EQ(countPhase(sim, "air"), 0u);
}

TEST(TrappedAir, BubbleRisesAndLeavesAtTheSurface) {
  const char* buoyancy = R"(
[effects.buoyancy]
[[effects.buoyancy.gas]]
phase = "air"
coefficient = {}
)";
  Simulation sim = poolWithBubble(fmt::format(buoyancy, "1.0"), {0.08, 0.05, 0.08}, 0.025);
  const size_t air0 = countPhase(sim, "air");
  const int air = sim.scene().phaseIndex("air");
  ASSERT_GT(air0, 40u);
  // The bubble's own particles, by id (a splash where it bursts may trap new air; that is not it).
  std::set<uint64_t> bubble;
  for (size_t i = 0; i < sim.particles().size(); ++i)
    if (sim.particles().phase[i] == air) bubble.insert(sim.particles().id[i]);
  auto bubbleLeft = [&] {
    size_t n = 0;
    for (uint64_t id : sim.particles().id) n += bubble.count(id);
    return n;
  };
  auto centreY = [&] {
    Real sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (bubble.count(sim.particles().id[i])) {
        sum += sim.particles().position[i].y;
        ++n;
      }
    return n ? sum / Real(n) : -1.0;
  };
  // Sampled every 20 ms while all of its air is still there (inside the water), the centre must
  // climb at every sample.
  std::vector<Real> path{centreY()};
  Real t = 0, firstLoss = -1, topAtFirstLoss = 0;
  while (t < 1.5 && bubbleLeft() > 0) {
    t += 0.02;
    sim.advanceTo(t);
    const size_t n = bubbleLeft();
    if (n < air0 && firstLoss < 0) {
      firstLoss = t;
      for (size_t i = 0; i < sim.particles().size(); ++i)
        if (bubble.count(sim.particles().id[i])) topAtFirstLoss = std::max(topAtFirstLoss, sim.particles().position[i].y);
    }
    if (firstLoss < 0) path.push_back(centreY());
    fmt::print("  t {:.2f}: {} of the bubble's air left, centre y {:.4f}; air {}, generated {}, deleted isolated {}, at the surface {}\n",
               t, n, centreY(), countPhase(sim, "air"), statistic(sim, "trapped_air", "generated"),
               statistic(sim, "trapped_air", "deleted_isolated"), statistic(sim, "trapped_air", "deleted_at_surface"));
  }
  fmt::print("bubble: {} air particles, centre y {:.4f} -> {:.4f} m over {} samples (20 ms) while whole; first loss at "
             "t = {:.2f} s with its top at y = {:.4f} m; all of it gone at t = {:.2f} s\n",
             air0, path.front(), path.back(), path.size(), firstLoss, topAtFirstLoss, t);
  ASSERT_GT(path.size(), 3u);
  for (size_t k = 1; k < path.size(); ++k) EXPECT_GT(path[k], path[k - 1]) << "sample " << k;
  // Nothing is removed while the bubble is inside: the first particle goes when the bubble's top
  // is within two spacings of the surface (0.2 m; the pool is a spacing higher where the bubble
  // pushes the water up). Measured 0.2003 m.
  EXPECT_GT(topAtFirstLoss, 0.18);
  EXPECT_EQ(bubbleLeft(), 0u);  // and all of it leaves there
}

// ---- the pour_glass scene: caps, ids, determinism, resume ---------------------------------------

// pour_glass at a coarser spacing (0.75 cm: 5 particles per layer from the tap, about 1 000 in
// all) and, for the cap test, a low air cap that is reached within a short run.
Scene smallPour(const std::string& end, int maxAir) {
  return loadScene("pour_glass", {"solver.particle_spacing=0.0075", "scene.end_time=" + end,
                                  fmt::format("effects.trapped_air.max_air={}", maxAir)});
}

TEST(PourGlass, CapsHoldAndIdsStayUnique) {
  Simulation sim(smallPour("0.6", 25));
  const int air = sim.scene().phaseIndex("air");
  size_t maxAir = 0, maxCount = 0;
  bool unique = true;
  sim.advanceTo(0.6, [&](const Simulation& s) {
    size_t n = 0;
    for (uint16_t p : s.particles().phase) n += p == air;
    maxAir = std::max(maxAir, n);
    maxCount = std::max(maxCount, s.particles().size());
    std::set<uint64_t> ids(s.particles().id.begin(), s.particles().id.end());
    unique &= ids.size() == s.particles().size();
  });
  fmt::print("pour (0.75 cm): {} particles at most, air at most {} (cap 25), generated {}, born {}, removed {}\n", maxCount,
             maxAir, statistic(sim, "trapped_air", "generated"), sim.counters().born, sim.counters().removedByEffects);
  EXPECT_TRUE(unique);
  EXPECT_LE(maxAir, 25u);
  EXPECT_EQ(maxAir, 25u);  // the cap is reached (so it is what stopped generation)
  EXPECT_GT(statistic(sim, "trapped_air", "generated"), 25);
}

TEST(PourGlass, BitIdenticalAcrossThreadsAndAfterResume) {
  const Scene scene = smallPour("0.3", 400);
  std::string reference;
  for (int threads : {1, 2, 3}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Simulation sim(scene);
    sim.advanceTo(0.15);  // a frame boundary, as in the resumed run below
    sim.advanceTo(0.3);
    if (reference.empty()) {
      reference = stateBytes(sim);
      fmt::print("pour (0.75 cm) at 0.3 s: {} particles, {} air, {} born, {} removed\n", sim.particles().size(),
                 countPhase(sim, "air"), sim.counters().born, sim.counters().removedByEffects);
      EXPECT_GT(countPhase(sim, "air"), 0u);
    } else {
      EXPECT_TRUE(stateBytes(sim) == reference) << threads << " threads";
    }
  }
  const fs::path dir = fs::temp_directory_path() / ("mf_test_pour_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Simulation first(scene);
  first.advanceTo(0.15);
  first.saveCheckpoint((dir / "ck.bin").string(), 4);
  Simulation resumed(scene);
  EXPECT_EQ(resumed.loadCheckpoint((dir / "ck.bin").string()), 4);
  EXPECT_EQ(resumed.nextId(), first.nextId());
  resumed.advanceTo(0.3);
  EXPECT_TRUE(stateBytes(resumed) == reference) << "resumed run differs";
  // The particle file holds every particle of the changed set.
  FrameInfo info;
  info.frame = 9;
  info.time = resumed.time();
  info.sceneName = "pour_glass";
  info.particleSpacing = resumed.particleSpacing();
  info.phaseNames = {"water", "air"};
  writeParticleFrame((dir / "p.vdb").string(), resumed.particles(), info);
  const ParticleFrame frame = readParticleFrame((dir / "p.vdb").string());
  EXPECT_EQ(frame.size(), resumed.particles().size());
  std::set<int64_t> ids(frame.id.begin(), frame.id.end());
  EXPECT_EQ(ids.size(), frame.size());
  fs::remove_all(dir);
}

// Air at its real density, 1.2 kg/m^3, with its added density of 300 kg/m^3 (PhaseSpec::addedDensity).
// A sphere of gas in a liquid starts up from rest at (rho_l - rho_g) / (rho_g + rho_l / 2) g
// = 1.99 g: it carries half its volume of liquid as added mass. Part of that the solve supplies
// by itself (air at 100 kg/m^3 without the key starts up at 2.2-2.5 g, not the 9 g its own
// density alone would give); the key carries the rest. Measured for one particle of air in a
// tank of still water (bench/bubble_bench): 1.54 g over the first step, 2.05 g over the first
// 3 ms (200 kg/m^3: 2.29 g; 500: 1.67 g); without the key the run stops in the first steps (the
// solve moves the air a spacing at a time to relieve the water around it). Bound: 10 % of the
// sphere's figure at 3 ms, about what moving the key by 50 kg/m^3 does (250 and 350 read 2.16
// and 1.94 g).
TEST(TrappedAir, ARealAirBubbleStartsUpAtTheAddedMassAcceleration) {
  Simulation sim(parseScene(bubbleInTankScene(1.2, 300, 0.0055), "bubble.toml"));
  const int air = sim.scene().phaseIndex("air");
  ASSERT_EQ(countPhase(sim, "air"), 1u);
  for (int k = 0; k < 6; ++k) sim.step(0.0005);
  Real vy = 0;
  for (size_t i = 0; i < sim.particles().size(); ++i)
    if (sim.particles().phase[i] == air) vy = sim.particles().velocity[i].y;
  const Real sphere = (1000.0 - 1.2) / (1.2 + 500.0) * 9.81, measured = vy / sim.time();
  fmt::print("a real-air bubble starts up at {:.3f} g over {:.4f} s (a sphere with its added mass: {:.3f} g)\n",
             measured / 9.81, sim.time(), sphere / 9.81);
  EXPECT_NEAR(measured / sphere, 1, 0.1);
  EXPECT_EQ(sim.counters().retries, 0u);
}

// The pour with real air (issue 21: air at 1.2 kg/m^3, 1:833). Over five runs with the water's
// viscosity moved by up to 2e-4 of itself: no watchdog retry, no water lost, every bubble gone at
// the surface (docs/scenes.md#real-air-pour_glass_real_air). As shipped: 530 air particles born,
// 522 removed at the surface. Bounds: no retry, at least 300 born, 95 % leaving at the surface.
TEST(PourGlass, TheRealAirVariantRunsCleanAtOneTo833) {
  const Scene scene = loadScene("pour_glass_real_air");
  const int water = scene.phaseIndex("water"), air = scene.phaseIndex("air");
  EXPECT_NEAR(scene.phases[size_t(water)].restDensity / scene.phases[size_t(air)].restDensity, 833.3, 0.1);
  Simulation sim(scene);
  // Frame by frame, as `multifluid sim` steps (each frame ends on its time): the run measured.
  for (int f = 1; f <= scene.lastFrame(); ++f) sim.advanceTo(f / scene.frameRate);  // a watchdog stop throws
  const double generated = statistic(sim, "trapped_air", "generated");
  const double atSurface = statistic(sim, "trapped_air", "deleted_at_surface");
  fmt::print("pour_glass_real_air: {} steps, {} retries, {} clamps, air generated {}, removed at the surface {}\n",
             sim.stepCount(), sim.counters().retries, sim.counters().wallClamps, generated, atSurface);
  EXPECT_EQ(sim.counters().retries, 0u);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
  for (uint64_t left : sim.leftDomainByPhase()) EXPECT_EQ(left, 0u);
  EXPECT_GE(generated, 300);
  EXPECT_GE(atSurface, 0.95 * generated);
}

}  // namespace
