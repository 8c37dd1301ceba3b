// `report stability`: sweeps over stiff and extreme settings. Each case is a short run; the
// simulator's own watchdog (Simulation::step) decides what happens to a bad step, and the report
// records whether the run got through, how compressed and how energetic it became, when trouble
// started and what the watchdog did about it. Every sweep runs with both pressure solvers; where
// a WCSPH parameter has no DFSPH meaning (stiffness), DFSPH sweeps its own (density_tolerance).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>

#include "report_stability_scenes.h"
#include "report_util.h"
#include "sim/bodies.h"
#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;

namespace mf::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kEnergyGrowthLimit = 0.05;  // flagged: a closed, viscous box should only lose energy

struct Case {
  std::string solver;  // solver.pressure
  std::string family;  // the WCSPH sweep this one stands beside (plots pair them in one row)
  std::string sweep, label, parameter;
  double value = 0;
  Scene scene;
  bool closed = true;  // no energy source: energy may only fall
  bool oneBody = false;  // a drop: it must end as one body (kBodyShare of its particles)
};

constexpr double kBodyShare = 0.9;  // a drop with less of its particles in its largest body broke up

struct Outcome {
  size_t particles = 0;
  uint64_t steps = 0, retries = 0, lost = 0;
  int64_t troubleStep = -1;       // first step the watchdog retried, or the step it gave up on
  double troubleTime = kNaN;
  double maxDensityError = 0, drift = kNaN, growth = kNaN, wall = 0, cpu = 0;
  double largestBody = kNaN;  // share of the particles in the largest body at the end (drops)
  bool stopped = false;
  std::string message;
  std::string status;  // stable, recovered, stopped, lost particles, broke up
  bool stable() const { return status == "stable" || status == "recovered"; }
  bool energyGrew(const Case& c) const { return c.closed && growth > kEnergyGrowthLimit; }
};

// ---- the sweeps --------------------------------------------------------------------------------

std::vector<Case> cases(const Options& opt) {
  const double end = opt.quick ? 0.1 : 0.3;
  const std::string drop = closedBoxScene(false, 1, 0.01, end);
  const bool q = opt.quick;
  std::vector<Case> list;
  std::string solver, family;  // of the cases `add` makes
  auto add = [&](const std::string& sweep, const std::string& label, const std::string& parameter, double value,
                 const std::string& text, std::vector<std::string> sets, bool closed = true, bool oneBody = false) {
    if (!opt.selected(sweep) && !opt.selected(family)) return;  // --only stiffness: DFSPH's stand-in too
    sets.push_back("solver.pressure=" + solver);
    list.push_back({solver, family, sweep, label, parameter, value,
                    parseScene(text, "<report:" + sweep + ">", sets), closed, oneBody});
  };
  // Each family of sweeps once per solver, WCSPH first, so that tables list the two side by side.
  auto both = [&](const std::string& name, const std::function<void(bool dfsph)>& sweepsOf) {
    family = name;
    for (const char* s : {"wcsph", "dfsph"}) solver = s, sweepsOf(solver == "dfsph");
  };
  both("stiffness", [&](bool dfsph) {
    if (!dfsph) {
      // Stiffness k of the drop, from soft to 100 times the default (1000 m^2/s^2).
      for (double k : q ? std::vector<double>{10, 1000} : std::vector<double>{10, 100, 400, 1000, 10000, 100000})
        add("stiffness", fmt::format("k={:g}", k), "phase.water.stiffness", k, drop, {"phase.water.stiffness=" + tomlReal(k)});
      return;
    }
    // DFSPH has no stiffness: how incompressible it is comes from the solve's tolerance on the
    // mean density error (default 5e-4), from loose (5 %) to tight (1e-5); the solve gives up
    // after solver.max_pressure_iterations (100), and a step it leaves unconverged is retried.
    for (double tol : q ? std::vector<double>{0.05, 5e-4} : std::vector<double>{0.05, 0.01, 1e-3, 5e-4, 1e-4, 1e-5})
      add("density_tolerance", fmt::format("tol={:g}", tol), "solver.density_tolerance", tol, drop,
          {"solver.density_tolerance=" + tomlReal(tol)});
  });
  both("density_ratio", [&](bool) {
    // Rest-density ratio of two layers, with each density formulation. DFSPH's constraint is the
    // density contrast whatever the formulation, but the density field the watchdog and the
    // implicit viscosity read follows it, so DFSPH runs both too.
    for (double r : q ? std::vector<double>{100} : std::vector<double>{1, 10, 100, 1000})
      for (const char* f : {"mass", "number"})
        add("density_ratio", fmt::format("1:{:g} {}", r, f), "rest-density ratio", r, layersText(r, f, end), {});
  });
  both("viscosity", [&](bool) {
    // Viscosity mu, from none to lava-like (basalt 100 - 1000 Pa s); DFSPH integrates it
    // implicitly, WCSPH explicitly under its viscous time-step limit.
    for (double mu : q ? std::vector<double>{1000} : std::vector<double>{0, 0.01, 0.1, 1, 10, 100, 1000})
      add("viscosity", fmt::format("mu={:g}", mu), "phase.water.viscosity", mu, drop, {"phase.water.viscosity=" + tomlReal(mu)});
  });
  both("dt_factor", [&](bool) {
    // Time-step factor f: cfl = 0.4 f, force_factor = 0.25 f; max_dt raised so that it does not
    // cap the step; last, the largest with retries forbidden. WCSPH's acoustic CFL limit is
    // cfl = 1; DFSPH's cfl is the fraction of a spacing the fastest particle moves per step.
    auto dtSets = [](double f) {
      return std::vector<std::string>{"solver.cfl=" + tomlReal(std::min(10.0, 0.4 * f)),
                                      "solver.force_factor=" + tomlReal(0.25 * f), "solver.max_dt=0.01"};
    };
    for (double f : q ? std::vector<double>{25} : std::vector<double>{0.5, 1, 2, 5, 10, 25})
      add("dt_factor", fmt::format("f={:g}", f), "time-step factor", f, drop, dtSets(f));
    auto sets = dtSets(25);
    sets.push_back("solver.max_retries=0");
    add("dt_factor", "f=25 no retries", "time-step factor", 25, drop, sets);
  });
  both("temperature", [&](bool) {
    // Temperature range between the heating and the cooling source.
    for (double dT : q ? std::vector<double>{1000} : std::vector<double>{0, 10, 100, 1000, 5000})
      add("temperature", fmt::format("dT={:g}", dT), "temperature range (K)", dT, temperatureText(dT, end), {}, false);
  });
  both("spacing", [&](bool) {
    // Particle spacing: 2 to 20 particles across the 0.1 m block, then the same 10 across at
    // 1 mm and at 10 m (Froude-scaled; stiffness unchanged).
    for (double s : q ? std::vector<double>{0.05} : std::vector<double>{0.05, 0.025, 0.01, 0.005})
      add("spacing", fmt::format("s={:g}m", s), "solver.particle_spacing", s, closedBoxScene(false, 1, s, end), {});
    if (!q)
      for (double scale : {0.01, 100.0})
        add("spacing", fmt::format("s={:g}m (scene x{:g})", 0.01 * scale, scale), "solver.particle_spacing",
            0.01 * scale, closedBoxScene(false, scale, 0.01 * scale, end), {});
  });
  both("surface_tension", [&](bool) {
    // Surface tension of a cube of water with no gravity, from water's to 14 000 times it: the
    // capillary time step (effects.surface_tension.time_step_factor) shrinks as 1/sqrt(sigma).
    // The energy measured (kinetic) is not conserved here: the tension turns surface energy into it.
    for (double sigma : q ? std::vector<double>{100} : std::vector<double>{0.0728, 1, 10, 100, 1000})
      add("surface_tension", fmt::format("sigma={:g}", sigma), "phase.water.surface_tension", sigma,
          tensionCubeText(sigma, 0.01, end), {}, false, true);
    // The same cube at 5 mm (8 000 particles): the grid-scale part of the force grows as 1/spacing.
    if (!q)
      for (double sigma : {1.0, 3.0, 10.0})
        add("surface_tension", fmt::format("sigma={:g} s=5mm", sigma), "phase.water.surface_tension", sigma,
            tensionCubeText(sigma, 0.005, end), {}, false, true);
  });
  return list;
}

// ---- one case ----------------------------------------------------------------------------------

// Energy growth is reported beside the status, not folded into it: it is measured in cases the
// watchdog has nothing against, and a sweep's limits would otherwise hide behind it.
std::string classify(const Outcome& o) {
  if (o.stopped) return "stopped";
  if (o.lost > 0) return "lost particles";
  if (o.largestBody < kBodyShare) return "broke up";
  return o.retries > 0 ? "recovered" : "stable";
}

// WCSPH: mechanicalEnergy's kinetic + gravitational + elastic energy of its state equation.
// DFSPH has no state equation and so stores no elastic energy (its pressure is a constraint
// force): kinetic + gravitational alone; the phase's stiffness, unused by DFSPH, must not count.
double energyOf(const Simulation& sim) {
  if (sim.scene().solver.pressure == PressureSolverChoice::WCSPH) return mechanicalEnergy(sim);
  const ParticleSet& ps = sim.particles();
  const Vec3 g = gravityOf(sim.scene());
  const double datumY = potentialDatumOf(sim.scene());
  double e = 0;
  for (size_t i = 0; i < ps.size(); ++i)
    e += ps.mass[i] * (0.5 * lengthSquared(ps.velocity[i]) -
                       (g.x * ps.position[i].x + g.y * (ps.position[i].y - datumY) + g.z * ps.position[i].z));
  return e;
}

Outcome runOne(const Case& c) {
  Outcome o;
  const auto t0 = Clock::now();
  const double cpu0 = processCpuSeconds();
  Simulation sim(c.scene);
  o.particles = sim.particles().size();
  const double e0 = energyOf(sim);
  double eMax = e0;
  try {
    sim.advanceTo(c.scene.endTime, [&](const Simulation& s) {
      eMax = std::max(eMax, energyOf(s));
      if (o.troubleStep < 0 && s.counters().retries > 0) {
        o.troubleStep = int64_t(s.stepCount()) - 1;  // the step just taken needed a retry
        o.troubleTime = s.time();
      }
    });
  } catch (const NumericalInstability& e) {
    o.stopped = true;
    o.message = e.what();
    if (o.troubleStep < 0) o.troubleStep = int64_t(sim.stepCount()), o.troubleTime = sim.time();
  }
  o.wall = secondsSince(t0);
  o.cpu = processCpuSeconds() - cpu0;
  const double e1 = energyOf(sim);
  o.steps = sim.stepCount();
  o.retries = sim.counters().retries;
  o.lost = sim.counters().removedOutOfDomain;
  o.maxDensityError = sim.counters().maxDensityError;
  if (c.oneBody) {
    const ParticleSet& ps = sim.particles();
    const std::vector<int32_t> phase(ps.phase.begin(), ps.phase.end());
    const FluidBodies b = findBodies(ps.position.data(), phase.data(), ps.size(), 1.5 * c.scene.solver.particleSpacing);
    size_t largest = 0;
    for (const FluidBody& body : b.bodies) largest = std::max(largest, body.size());
    o.largestBody = ps.size() ? double(largest) / double(ps.size()) : kNaN;
  }
  if (e0 > 0) o.drift = (e1 - e0) / e0, o.growth = (eMax - e0) / e0;
  o.status = classify(o);
  if (o.message.empty() && o.retries > 0)
    o.message = fmt::format("watchdog halved dt on {} step attempt(s); run completed", o.retries);
  return o;
}

// ---- output ------------------------------------------------------------------------------------

Table resultTable(const std::vector<Case>& cs, const std::vector<Outcome>& os) {
  Table t;
  t.header = {"solver", "sweep", "case", "parameter", "value", "particles", "end_time_s", "status", "stable", "steps", "retries",
              "first_trouble_step", "first_trouble_time_s", "max_density_error", "energy_drift", "energy_growth_max",
              "lost_particles", "largest_body", "wall_s", "cpu_s", "message"};
  for (size_t k = 0; k < cs.size(); ++k) {
    const Case& c = cs[k];
    const Outcome& o = os[k];
    t.add({c.solver, c.sweep, c.label, c.parameter, fmtNumber(c.value, 6), std::to_string(o.particles), fmtNumber(c.scene.endTime, 4),
           o.status, o.stable() ? "yes" : "no", std::to_string(o.steps), std::to_string(o.retries),
           o.troubleStep < 0 ? "-" : std::to_string(o.troubleStep), fmtNumber(o.troubleTime, 4),
           fmtNumber(o.maxDensityError, 3), fmtNumber(o.drift, 3), fmtNumber(o.growth, 3), std::to_string(o.lost),
           fmtNumber(o.largestBody, 3),
           fmt::format("{:.2f}", o.wall), fmt::format("{:.2f}", o.cpu), o.message});
  }
  return t;
}

// What one stability figure shows: a value per case on a log axis, one panel per sweep.
struct Figure {
  std::string name, title, ylabel;
  double ymin, ymax, reference;  // a dashed line at `reference` (0: none)
  std::function<double(const Outcome&)> value;
};

// One row of panels per family of sweeps, one column per solver (WCSPH left, DFSPH right), every
// case coloured by its outcome (stopped runs as crosses).
std::string figureScript(const Figure& f, const std::vector<Case>& cs, const std::vector<Outcome>& os) {
  std::vector<std::string> families, solvers;
  for (const auto& c : cs) {
    if (std::find(families.begin(), families.end(), c.family) == families.end()) families.push_back(c.family);
    if (std::find(solvers.begin(), solvers.end(), c.solver) == solvers.end()) solvers.push_back(c.solver);
  }
  const int cols = int(solvers.size()), rows = int(families.size());
  std::string s = fmt::format(R"gp(set terminal pngcairo size {},{} noenhanced font "sans,9"
set output "{}.png.tmp"
set multiplot layout {},{} title "{}\ngreen: stable; orange: recovered by watchdog retries; red: lost particles or a drop broken up; red cross: stopped by the watchdog"
set logscale y
set yrange [{}:{}]
set grid ytics
set xtics rotate by 30 right
set ylabel "{}"
)gp",
                              cols * 550, rows * 380, f.name, rows, cols, escapeGnuplot(f.title), f.ymin, f.ymax,
                              escapeGnuplot(f.ylabel));
  if (f.reference > 0) s += fmt::format("set arrow from graph 0, first {0} to graph 1, first {0} nohead dt 2 lc rgb \"#555555\"\n", f.reference);
  for (const auto& family : families)
    for (const auto& solver : solvers) {
    std::string data, tics, sweep;
    int x = 0;
    for (size_t k = 0; k < cs.size(); ++k) {
      if (cs[k].family != family || cs[k].solver != solver) continue;
      sweep = cs[k].sweep;
      const Outcome& o = os[k];
      const int colour = o.stable() ? (o.retries > 0 ? 0xff7f0e : 0x2ca02c) : 0xd62728;
      const double y = std::min(f.ymax, std::max(f.ymin, f.value(o)));
      // gnuplot takes variable columns in the order point type, then colour.
      data += fmt::format("{} {:.6g} {} {}\n", x, y, o.stopped ? 2 : 7, colour);
      tics += fmt::format("{}\"{}\" {}", tics.empty() ? "" : ", ", escapeGnuplot(cs[k].label), x);
      ++x;
    }
    if (x == 0) {  // this family has no case of this solver (--only): leave its panel empty
      s += "set multiplot next\n";
      continue;
    }
    s += fmt::format("set title \"{}: {}\"\nset xrange [-0.5:{}]\nset xtics ({})\n", solver, sweep, x - 0.5, tics);
    s += "plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle\n" + data + "e\n";
    }
  return s + "unset multiplot\n";
}

std::vector<Figure> figures(double watchdogLimit) {
  return {{"stability", fmt::format("Largest compression (rho - rho0)/rho0 of accepted steps per case (stopped runs drawn at the watchdog's limit {})", watchdogLimit),
           "max density error", 1e-4, 2, 0,
           [=](const Outcome& o) { return o.stopped ? watchdogLimit : o.maxDensityError; }},
          {"stability_energy",
           fmt::format("Energy growth: max over steps of (E - E0)/E0 per case (up to the stop for stopped runs; dashed: {:.0f} %)",
                       100 * kEnergyGrowthLimit),
           "energy growth (log)", 1e-4, 1e3, kEnergyGrowthLimit, [](const Outcome& o) { return o.growth; }}};
}

// Per sweep: which cases held and which did not, with the watchdog's word on the first failure.
std::string limits(const std::vector<Case>& cs, const std::vector<Outcome>& os) {
  std::string out;
  std::string current;
  auto key = [&](size_t k) { return cs[k].solver + " " + cs[k].sweep; };
  for (size_t k = 0; k < cs.size(); ++k) {
    if (key(k) == current) continue;
    current = key(k);
    std::vector<std::string> good, bad, grew;
    std::string firstBad;
    for (size_t j = k; j < cs.size(); ++j) {
      if (key(j) != current) continue;
      const std::string item = cs[j].label + (os[j].retries > 0 && os[j].stable() ? " (with retries)" : "");
      (os[j].stable() ? good : bad).push_back(os[j].stable() ? item : cs[j].label + ": " + os[j].status);
      if (!os[j].stable() && firstBad.empty() && !os[j].message.empty()) firstBad = os[j].message;
      if (os[j].energyGrew(cs[j])) grew.push_back(fmt::format("{} (+{:.0f} %)", cs[j].label, 100 * os[j].growth));
    }
    auto join = [](const std::vector<std::string>& v) {
      std::string s;
      for (const auto& x : v) s += (s.empty() ? "" : "; ") + x;
      return s.empty() ? std::string("none") : s;
    };
    out += fmt::format("- **{}**: stable: {}. Not stable: {}.", current, join(good), join(bad));
    if (!grew.empty()) out += fmt::format(" Energy grew by more than {:.0f} %: {}.", 100 * kEnergyGrowthLimit, join(grew));
    if (!firstBad.empty()) out += fmt::format(" First stop message: `{}`", firstBad);
    out += "\n";
  }
  return out;
}

std::string page(const Options& opt, const Machine& machine, const Table& t, const std::vector<Case>& cs,
                 const std::vector<Outcome>& os, double seconds) {
  std::string out = fmt::format(
      "# Stability on stiff and extreme cases\n\n"
      "Generated by `{}` on {}.\n\n**Machine**: {}; load average {} at the end. Wall times measured there.\n\n"
      "**Sweep**: {}. Each case is a short run of one scene with one value changed from its base:\n\n"
      "- `stiffness`, `viscosity`, `dt_factor`, `spacing`: a 0.1 m cube of water (1 cm spacing, 1000 particles, "
      "k = 1000, mu = 0.1 Pa s) thrown at 2 m/s at the floor of a closed 0.1 x 0.2 x 0.1 m box "
      "(the drop of tests/test_watchdog.cpp), for {} s. The time-step factor f sets `solver.cfl` = 0.4 f (at most 10; "
      "cfl = 1 is the acoustic CFL limit) and `solver.force_factor` = 0.25 f, with `max_dt` = 0.01 s. The "
      "scaled spacing cases are the same drop at 1/100 and 100 times the size, speeds and times scaled by "
      "sqrt(size) (Froude similarity), stiffness kept.\n"
      "- `density_ratio`: 5 cm of water under 5 cm of a fluid with rest density 1000/ratio, at rest, per density "
      "formulation.\n"
      "- `temperature`: 10 cm of water (thermal expansion 1e-3/K, diffusivity 2e-4 m^2/s) heated from below by a "
      "source at 20 + dT/2 and cooled from above by one at 20 - dT/2 (rate 5/s).\n"
      "- `surface_tension`: a 0.1 m cube of water (1 cm spacing, 1000 particles, mu = 1e-3 Pa s, k = 1000) at rest "
      "with no gravity, pulled into a ball by its surface tension sigma (DFSPH: the fitted curvature; WCSPH: the "
      "divergence of the normal), from water's 0.0728 N/m to 1000 N/m; then at 5 mm spacing (8000 particles) for "
      "1, 3 and 10 N/m.\n\n"
      "**Solvers**: every sweep runs with `solver.pressure = \"wcsph\"` and again with `\"dfsph\"` (column "
      "`solver`; in the figures WCSPH left, DFSPH right, one row per sweep). DFSPH has no stiffness: in place of "
      "the `stiffness` sweep it sweeps `solver.density_tolerance` (the mean density error its constant-density "
      "solve stops at, default 5e-4; at most `solver.max_pressure_iterations` = 100 iterations). Its `solver.cfl` "
      "bounds the flow, dt <= cfl spacing / v_max (WCSPH's: dt <= cfl h / (sqrt(k) + v_max)). `density_ratio` "
      "runs both formulations on DFSPH too (`density_formulation` is the density WCSPH's state equation reads; DFSPH's "
      "constraint is the density contrast sum_j V_j W_ij for either formulation, but the density field its "
      "watchdog and its implicit viscosity read follows the formulation, so both run). Outside `dt_factor` the cases keep "
      "the default `solver.max_dt` = 1 ms, which is what sets DFSPH's step there; `dt_factor` lifts it to 10 ms "
      "for both solvers.\n\n"
      "**Columns**: `status` is `stable` (ran to the end, nothing retried), `recovered` (ran to the end; the "
      "watchdog retried steps with half the dt), `stopped` (the watchdog gave up after `solver.max_retries` "
      "halvings and threw its message, quoted below), `lost particles` (particles left the domain) or `broke up` "
      "(a drop ended with under {:.0f} % of its particles in its largest body, `largest_body`: bodies linked within "
      "1.5 spacings, as issue 23 counts them); `stable` "
      "is yes for the first two. `max_density_error` is the largest (rho - rho0)/rho0 after any accepted step "
      "(Simulation counters; the watchdog rejects steps above 0.5). Energy E = kinetic + gravitational (above "
      "the floor) + elastic, the last k (ln(rho/rho0) + rho0/rho - 1) per unit mass where rho > rho0 (the work "
      "of P = k (rho - rho0) with the SPH density; for DFSPH, which has no state equation, kinetic + gravitational "
      "alone); `energy_drift` = (E_end - E_0)/E_0 and "
      "`energy_growth_max` = max over steps of (E - E_0)/E_0. A closed viscous box should only lose energy; "
      "growth above {:.0f} % is listed under the limits (not for `temperature`, where the sources do work, nor for `surface_tension`, where the tension does). "
      "`first_trouble_step` is the first step the watchdog had to retry, or the step it stopped at.\n\n",
      opt.commandLine, utcNow(), machine.describe(), loadAverage(), opt.quick ? "quick (the CI check, not for conclusions)" : "full",
      opt.quick ? 0.1 : 0.3, 100 * kBodyShare, 100 * kEnergyGrowthLimit);
  out += "## Limits found\n\n" + limits(cs, os) +
         "\n![largest compression per case](stability.png)\n\n![energy growth per case](stability_energy.png)\n\n"
         "## All cases\n\n";
  out += t.markdown({"solver", "sweep", "case", "particles", "status", "steps", "retries", "first_trouble_step",
                     "max_density_error", "energy_drift", "energy_growth_max", "lost_particles", "largest_body", "wall_s", "cpu_s"}) +
         "\n## Watchdog messages\n\n";
  for (size_t k = 0; k < cs.size(); ++k)
    if (!os[k].message.empty()) out += fmt::format("- {} {} {}: {}\n", cs[k].solver, cs[k].sweep, cs[k].label, os[k].message);
  out += fmt::format("\nTotal time of this report: {} ({}).\n", formatDuration(seconds), machine.describe());
  return out;
}

}  // namespace

int runStability(const Options& opt, const Machine& machine) {
  const auto start = Clock::now();
  const std::vector<Case> cs = cases(opt);
  if (cs.empty()) return 0;
  std::vector<Outcome> os;
  for (const Case& c : cs) {
    os.push_back(runOne(c));
    const Outcome& o = os.back();
    fmt::print(stderr, "[stability {}/{}] {} {} {}: {} particles, {} steps, {}, retries {}, max density error {}  {:.2f} s  (elapsed {})\n",
               os.size(), cs.size(), c.solver, c.sweep, c.label, o.particles, o.steps, o.status, o.retries,
               fmtNumber(o.maxDensityError), o.wall, formatDuration(secondsSince(start)));
  }
  const fs::path out(opt.out);
  const Table t = resultTable(cs, os);
  writeText((out / "stability.csv").string(), t.csv());
  bool plotted = true;
  for (const Figure& f : figures(cs.front().scene.solver.maxDensityError))
    plotted &= plot(opt, f.name, figureScript(f, cs, os), (out / (f.name + ".png")).string());
  writeText((out / "stability.md").string(), page(opt, machine, t, cs, os, secondsSince(start)));
  fmt::print(stderr, "report stability: {} cases in {} on {}; wrote {}\n", cs.size(), formatDuration(secondsSince(start)),
             machine.describe(), (out / "stability.md").string());
  return plotted ? 0 : 4;
}

}  // namespace mf::report
