// Phase change (Mueller et al. 2005, section 5.2): evaporation at cavitation sites, mass kept,
// condensation in cold water; the boiling scene bit-identical across threads and after resume,
// and vapour only where and when the rules allow.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <unistd.h>

#include "particle_test_util.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/solids.h"

namespace fs = std::filesystem;

namespace {

using namespace mf;
using namespace mf::test_util;

// A pool of water at 105 deg C with one cavitation site at the bottom centre; no heat flow, so
// only the phase change acts on temperatures. `extra` is appended (more tables).
std::string boilingPool(Real temperature, const std::string& extra = "") {
  return fmt::format(R"(
[scene]
name = "boil"
end_time = 1.0
domain_min = [-0.05, -0.05, -0.05]
domain_max = [0.17, 0.3, 0.17]
[solver]
particle_spacing = 0.01
density_formulation = "number"
max_dt = 0.002
[[phase]]
name = "water"
rest_density = 1000.0
viscosity = 0.2
[[phase]]
name = "vapour"
rest_density = 300.0
viscosity = 0.02
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.12, 0.25, 0.12]
open_top = true
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.12, 0.08, 0.12]
temperature = {}
[effects.gravity]
[effects.viscosity]
[effects.phase_change]
liquid = "water"
vapour = "vapour"
sites = 1
site_min = [0.06, 0.005, 0.06]
site_max = [0.06, 0.005, 0.06]
site_radius = 1.0
{})",
                     temperature, extra);
}

TEST(PhaseChange, EvaporatesAtTheSiteKeepsMassAndCondensesWhenCooled) {
  Simulation sim(parseScene(boilingPool(105.0), "boil.toml"));
  const size_t n0 = sim.particles().size();
  const Real m = sim.particles().mass[0];
  const int vapour = sim.scene().phaseIndex("vapour");
  // Every particle starts hot, but only the site (and then vapour's neighbours) nucleates.
  sim.step(1.0);
  const size_t first = countPhase(sim, "vapour");
  for (size_t i = 0; i < sim.particles().size(); ++i) {
    if (sim.particles().phase[i] == vapour) {
      EXPECT_LE(length(sim.particles().position[i] - Vec3(0.06, 0.005, 0.06)), 0.0101);
    }
  }
  EXPECT_GE(first, 1u);
  EXPECT_LE(first, 7u);  // the site and at most its 6 lattice neighbours within one spacing
  sim.advanceTo(0.1);
  Real mass = 0, maxCompression = 0;
  for (size_t i = 0; i < sim.particles().size(); ++i) {
    mass += sim.particles().mass[i];
    if (sim.particles().phase[i] == vapour)
      maxCompression = std::max(maxCompression, sim.particles().density[i] / sim.particles().restDensity[i] - 1);
  }
  const size_t vapourCount = countPhase(sim, "vapour");
  fmt::print("boiling pool: {} vapour after one step, {} after 0.1 s ({} left at the surface), largest vapour compression "
             "{:.1f} %\n",
             first, vapourCount, statistic(sim, "phase_change", "left_at_surface"), 100 * maxCompression);
  EXPECT_GT(vapourCount, first);  // the bubble grows into the hot water around it
  // Mass is kept on evaporation: every particle still has the water particle's mass (masses are
  // copied, never recomputed; the tolerance is only the rounding of summing ~1 000 equal terms).
  for (size_t i = 0; i < sim.particles().size(); ++i) EXPECT_EQ(sim.particles().mass[i], m);
  EXPECT_NEAR(mass, m * Real(sim.particles().size()), 1e-12 * mass);
  EXPECT_EQ(sim.particles().size() + sim.counters().removedByEffects + sim.counters().removedOutOfDomain, n0);
  // The expansion is held to 25 % compression when the step ends; the next step's motion adds
  // a little (the watchdog stops at 50 %).
  EXPECT_LT(maxCompression, 0.5);
  // Cooled below 100 - 2 deg C, all vapour condenses in the next step.
  for (Real& T : sim.mutableParticles().temperature) T = 50;
  sim.step(1.0);
  EXPECT_EQ(countPhase(sim, "vapour"), 0u);
  EXPECT_EQ(statistic(sim, "phase_change", "condensed"),
            statistic(sim, "phase_change", "evaporated") - statistic(sim, "phase_change", "left_at_surface"));
  for (size_t i = 0; i < sim.particles().size(); ++i) EXPECT_EQ(sim.particles().restDensity[i], 1000.0);
}

TEST(PhaseChange, LatentHeatSetsWhenTheSiteEvaporatesWhateverTheStep) {
  // The pool 6 K above boiling, with L / c_p = 10 K: the site's water takes its 6 K of superheat
  // into its latent store and waits. A heater around the site (held at 120 deg C, rate 2 /s; no
  // conduction) then delivers r (120 - 100) = 40 K/s into the store, since the water is held at
  // 100: the store reaches 10 K at t* = (10 - 6) / 40 = 0.1 s exactly, for any step. Without
  // the latent heat the site evaporates in the first step.
  const std::string heater = R"(
[effects.heat_diffusion]
[[effects.heat_diffusion.source]]
min = [0.045, -0.01, 0.045]
max = [0.075, 0.02, 0.075]
temperature = 120.0
rate = 2.0
)";
  const Real tStar = 0.1;
  for (const char* cfl : {"0.1", "0.4"}) {
    Simulation sim(parseScene(boilingPool(106.0, heater), "latent.toml",
                              {"effects.phase_change.latent_heat=10", std::string("solver.cfl=") + cfl}));
    EXPECT_TRUE(sim.particles().has(Attribute::Latent));
    Real first = -1, dt = 0;
    while (sim.time() < 0.15 && first < 0) {
      const Real t0 = sim.time();
      sim.step(1.0);
      dt = std::max(dt, sim.time() - t0);
      if (statistic(sim, "phase_change", "evaporated") > 0) first = sim.time();
    }
    fmt::print("latent heat, cfl {}: the site evaporates at {:.4f} s (t* = {} s, steps up to {:.4f} s)\n", cfl, first, tStar, dt);
    // Within one step of t* (the store is filled at the end of the step that crosses it).
    EXPECT_GE(first, tStar - 1e-9) << cfl;
    EXPECT_LE(first, tStar + dt + 1e-9) << cfl;
    // Condensing gives the latent heat back: vapour cooled to 50 deg C condenses at 60.
    const int water = sim.scene().phaseIndex("water"), vapour = sim.scene().phaseIndex("vapour");
    std::vector<uint64_t> ids;
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (sim.particles().phase[i] == vapour) {
        ids.push_back(sim.particles().id[i]);
        sim.mutableParticles().temperature[i] = 50;
      }
    ASSERT_FALSE(ids.empty());
    sim.step(1.0);
    for (size_t i = 0; i < sim.particles().size(); ++i)
      if (std::find(ids.begin(), ids.end(), sim.particles().id[i]) != ids.end()) {
        EXPECT_EQ(sim.particles().phase[i], water);
        EXPECT_NEAR(sim.particles().temperature[i], 60.0, 1.0);  // 50 + 10, and one step of the heater (<= 70 K/s x dt)
      }
  }
  Simulation plain(parseScene(boilingPool(106.0, heater), "latent.toml"));
  plain.step(1.0);
  EXPECT_GE(statistic(plain, "phase_change", "evaporated"), 1.0);
}

TEST(Boiling, BitIdenticalAcrossThreadsAndAfterResume) {
  // The boiling scene at a 1 cm spacing, long enough for flames to heat the glass and the
  // first vapour to form (the glass bottom is started hot).
  const Scene scene = loadScene("boiling", {"solver.particle_spacing=0.01", "scene.end_time=0.4",
                                            "effects.flame_heating.wall_temperature=300", "fluid.0.temperature=95"});
  std::string reference;
  for (int threads : {1, 2, 3}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Simulation sim(scene);
    sim.advanceTo(0.2);
    sim.advanceTo(0.4);
    if (reference.empty()) {
      reference = stateBytes(sim);
      fmt::print("boiling (1 cm) at 0.4 s: {} water, {} vapour, {} flame; evaporated {}, condensed {}, left {}; glass {:.1f} C\n",
                 countPhase(sim, "water"), countPhase(sim, "vapour"), countPhase(sim, "flame"),
                 statistic(sim, "phase_change", "evaporated"), statistic(sim, "phase_change", "condensed"),
                 statistic(sim, "phase_change", "left_at_surface"), statistic(sim, "flame_heating", "wall_temperature"));
      EXPECT_GT(statistic(sim, "phase_change", "evaporated"), 0);
      EXPECT_GT(countPhase(sim, "flame"), 0u);
    } else {
      EXPECT_TRUE(stateBytes(sim) == reference) << threads << " threads";
    }
  }
  const fs::path dir = fs::temp_directory_path() / ("mf_test_boil_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Simulation first(scene);
  first.advanceTo(0.2);
  first.saveCheckpoint((dir / "ck.bin").string(), 5);
  Simulation resumed(scene);
  EXPECT_EQ(resumed.loadCheckpoint((dir / "ck.bin").string()), 5);
  EXPECT_EQ(statistic(resumed, "flame_heating", "wall_temperature"), statistic(first, "flame_heating", "wall_temperature"));
  resumed.advanceTo(0.4);
  EXPECT_TRUE(stateBytes(resumed) == reference) << "resumed run differs";
  fs::remove_all(dir);
}


TEST(Boiling, VapourOnlyAtTheSiteAboveBoilingWhileTheWaterWarms) {
  // The boiling scene from 0 deg C at a 1 cm spacing (about 650 water particles) with one
  // cavitation site at a known point on the bottom: every particle that turns to vapour was
  // above the boiling temperature (saturated vapour starts at exactly 100 deg C, min(T, 100)),
  // and either lies within site_radius of the site or joins vapour that was there the step
  // before (a growing bubble) away from the glass (the heated layer, wall_distance); the first
  // vapour is at the site. The water's
  // mean temperature, sampled every 0.1 s, never falls while the flames burn.
  const Vec3 site(0.0, 0.005, 0.0);
  const Real end = 3.0;
  const Scene scene = loadScene("boiling", {"solver.particle_spacing=0.01", fmt::format("scene.end_time={}", end),
                                            "effects.phase_change.sites=1", "effects.phase_change.site_min=[0.0, 0.005, 0.0]",
                                            "effects.phase_change.site_max=[0.0, 0.005, 0.0]",
                                            // the heated layer at this spacing: one layer, 1.1 cm as in the scene
                                            "effects.phase_change.wall_distance=1.1"});
  Simulation sim(scene);
  const int water = scene.phaseIndex("water"), vapour = scene.phaseIndex("vapour");
  const Real s = sim.particleSpacing(), h = sim.kernels().h;
  Real siteRadius = 0, wallDistance = 0, boiling = 0;
  for (const EffectSpec& e : scene.effects)
    if (e.name == "phase_change") {
      siteRadius = e.number("site_radius") * s;
      wallDistance = e.number("wall_distance") * s;
      boiling = e.number("boiling_temperature");
    }
  ASSERT_GT(siteRadius, 0);
  const SolidSpec& glass = scene.solids.at(0);
  std::map<uint64_t, uint16_t> before;  // id -> phase at the end of the previous step
  std::vector<Vec3> vapourBefore;
  for (size_t i = 0; i < sim.particles().size(); ++i) before[sim.particles().id[i]] = sim.particles().phase[i];
  uint64_t born = 0, atSite = 0, grown = 0, misplaced = 0, notHot = 0;
  Real firstVapour = -1, firstDistance = -1;
  auto waterMean = [&](const Simulation& sm) {
    Real sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < sm.particles().size(); ++i)
      if (sm.particles().phase[i] == water) {
        sum += sm.particles().temperature[i];
        ++n;
      }
    return sum / Real(n);
  };
  std::vector<Real> means{waterMean(sim)};
  std::vector<double> flames{0};
  Real lastTime = 0;
  for (int k = 1; Real(k) * 0.1 <= end + 1e-9; ++k) {
    sim.advanceTo(Real(k) * 0.1, [&](const Simulation& sm) {
      const ParticleSet& ps = sm.particles();
      // The neighbour lists were built at the step's start; two particles have come closer or
      // gone apart by at most 2 vmax dt since.
      Real vmax = 0;
      for (const Vec3& v : ps.velocity) vmax = std::max(vmax, length(v));
      const Real reach = h + 2 * vmax * (sm.time() - lastTime);
      lastTime = sm.time();
      std::vector<Vec3> vapourNow;
      for (size_t i = 0; i < ps.size(); ++i) {
        if (ps.phase[i] != vapour) continue;
        vapourNow.push_back(ps.position[i]);
        const auto it = before.find(ps.id[i]);
        if (it == before.end() || it->second != water) continue;
        ++born;
        const Vec3 x = ps.position[i];
        notHot += ps.temperature[i] != boiling;
        const bool nearSite = length(x - site) <= siteRadius * (1 + 1e-9);
        bool nextToVapour = false;
        for (const Vec3& v : vapourBefore) nextToVapour |= length(v - x) < reach;
        const bool onGlass = !insideFluidRegion(glass, x, -wallDistance);
        if (firstVapour < 0) {
          firstVapour = sm.time();
          firstDistance = length(x - site);
        }
        atSite += nearSite;
        grown += !nearSite && nextToVapour && !onGlass;
        misplaced += !nearSite && !(nextToVapour && !onGlass);
      }
      before.clear();
      for (size_t i = 0; i < ps.size(); ++i) before[ps.id[i]] = ps.phase[i];
      vapourBefore = std::move(vapourNow);
    });
    means.push_back(waterMean(sim));
    flames.push_back(statistic(sim, "flame_heating", "flames_under_glass"));
  }
  std::string path;
  for (size_t k = 0; k < means.size(); k += 5) path += fmt::format(" {:.1f}", means[k]);
  fmt::print("boiling (1 cm, one site): first vapour at t = {:.3f} s, {:.4f} m from the site; {} evaporations: {} at the site, "
             "{} growing a bubble, {} elsewhere, {} not from above {} C; condensed {}, left {}; water mean T every 0.5 s:{}\n",
             firstVapour, firstDistance, born, atSite, grown, misplaced, notHot, boiling,
             statistic(sim, "phase_change", "condensed"), statistic(sim, "phase_change", "left_at_surface"), path);
  ASSERT_GT(firstVapour, 0) << "no vapour within " << end << " s";
  EXPECT_LE(firstDistance, siteRadius * (1 + 1e-9));
  EXPECT_GT(atSite, 0u);
  EXPECT_EQ(misplaced, 0u);
  EXPECT_EQ(notHot, 0u);
  EXPECT_EQ(double(born), statistic(sim, "phase_change", "evaporated"));
  EXPECT_EQ(double(atSite), statistic(sim, "phase_change", "evaporated_at_sites"));
  for (size_t k = 1; k < means.size(); ++k)
    if (flames[k] > 0) {
      EXPECT_GE(means[k], means[k - 1]) << "t = " << 0.1 * double(k) << " s";
    }
}

}  // namespace
