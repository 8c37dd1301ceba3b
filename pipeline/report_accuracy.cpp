// `report accuracy`: each reference problem run over a ladder of settings (particle spacing,
// time-step factor, and where it matters the formulation); wall time and error against the
// reference per setting, the Pareto front, and the best setting for a few time budgets.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>

#include "report_util.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;

namespace mf::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kG = 9.81;

/// One rung of a ladder. `dtFactor` multiplies every time-step criterion the problem is limited
/// by (cfl 0.4 and force_factor 0.25 by default; the diffusion stability factor 0.5 for heat).
struct Setting {
  double spacing = 0;
  double dtFactor = 1;
  std::string variant;   // the formulation choice where the problem has one
  std::string label;     // short name for tables and plots
};

struct Measured {
  size_t particles = 0;
  uint64_t steps = 0;
  double wall = 0;        // s: construction and stepping, without our measurement callbacks
  double cpu = 0;         // CPU s of all threads over the same span
  double load = 0;        // 1-minute load average after the run
  double error = kNaN;    // the problem's error (NaN: the run stopped)
  std::vector<double> extras;
  std::string status = "ok";
  std::vector<std::pair<double, double>> curve;  // dam break: (T, Z) for the front plot
};

struct Problem {
  std::string name, title, errorName, errorDefinition, method;
  std::vector<std::string> extraColumns;
  std::vector<Setting> ladder;
  std::function<Measured(const Setting&)> run;
  int altExtra = -1;       // an extra that is a second error with its own Pareto front, or -1
  std::string altName;     // its name in plots and tables
  double errorOf(const Measured& m, bool alt) const {
    return !alt ? m.error : size_t(altExtra) < m.extras.size() ? m.extras[size_t(altExtra)] : kNaN;
  }
};

// Wall time of construction and stepping; the time our own per-step measurements take is
// subtracted so that the figures are what a user's run would cost.
struct Stopwatch {
  Clock::time_point t0 = Clock::now();
  double cpu0 = processCpuSeconds();
  double excluded = 0, excludedCpu = 0;
  double elapsed() const { return secondsSince(t0) - excluded; }
  double cpu() const { return processCpuSeconds() - cpu0 - excludedCpu; }
  template <class F>
  void exclude(F&& f) {
    const auto c0 = Clock::now();
    const double cpu = processCpuSeconds();
    f();
    excluded += secondsSince(c0);
    excludedCpu += processCpuSeconds() - cpu;
  }
};

std::vector<std::string> dtOverrides(double f) {
  return {"solver.cfl=" + tomlReal(0.4 * f), "solver.force_factor=" + tomlReal(0.25 * f)};
}

// Runs `advance` on a fresh simulation; a watchdog stop is a result, not a failure of the report.
Measured runCase(const Scene& scene, const std::function<void(Simulation&, Stopwatch&)>& advance) {
  Measured m;
  Stopwatch sw;
  Simulation sim(scene);
  m.particles = sim.particles().size();
  try {
    advance(sim, sw);
  } catch (const NumericalInstability& e) {
    m.error = kNaN;
    m.status = std::string("stopped: ") + e.what();
  }
  m.wall = sw.elapsed();
  m.cpu = sw.cpu();
  m.load = loadAverage1();
  m.steps = sim.stepCount();
  return m;
}

// ---- dam break against Martin & Moyce (1952) ---------------------------------------------------

// Martin & Moyce 1952, Table 2 (n^2 = 2, a = 2.25 in): surge front Z = x/a at T = t sqrt(2g/a).
// Verbatim from /work/shared/validation/martin_moyce_1952.csv, series ocellaris_table2 (copied
// here so that the report runs anywhere).
const std::vector<std::pair<double, double>> kSurgeFront = {
    {0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56},
    {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22}, {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11}};
// Table 6: residual column height H = h/(2a) at tau = t sqrt(g/a) (martin_moyce_1952_column_height.csv).
const std::vector<std::pair<double, double>> kColumnHeight = {
    {0.56, 0.94}, {0.77, 0.89}, {0.93, 0.83}, {1.08, 0.78}, {1.28, 0.72}, {1.46, 0.67}, {1.66, 0.61}, {1.84, 0.56},
    {2.00, 0.50}, {2.21, 0.44}, {2.45, 0.39}, {2.70, 0.33}, {3.06, 0.28}, {3.44, 0.22}, {4.20, 0.17}, {5.25, 0.11},
    {7.40, 0.06}};
constexpr double kA = 0.05715;      // column base a (configs/dam_break.toml)
constexpr double kTMax = 3.0;       // compare the points with T <= 3 (the issue's range)
constexpr double kShiftT = 0.175;   // gate-release shift in T used by Lethe's Martin-Moyce example

// Linear interpolation in a time series (t ascending); before its start the first value.
double interpolate(const std::vector<std::pair<double, double>>& s, double t) {
  if (t <= s.front().first) return s.front().second;
  auto hi = std::lower_bound(s.begin(), s.end(), t, [](const auto& p, double v) { return p.first < v; });
  if (hi == s.end()) return s.back().second;
  const auto lo = hi - 1;
  return lo->second + (hi->second - lo->second) * (t - lo->first) / (hi->first - lo->first);
}

// RMS of model(T - shift) - data over the points with T <= tMax; model(T) before 0 is model(0)
// (the column stands still until released).
double rmsAgainst(const std::vector<std::pair<double, double>>& data, double tMax, double shift,
                  const std::function<double(double)>& model) {
  double sum = 0;
  int n = 0;
  for (const auto& [T, v] : data)
    if (T <= tMax + 1e-9) {
      sum += std::pow(model(std::max(0.0, T - shift)) - v, 2);
      ++n;
    }
  return std::sqrt(sum / n);
}

// The front: the 99.9th percentile of x (one stray droplet does not count), plus half a spacing
// for the particle's own extent, so that the column at rest reads exactly Z = 1.
double surgeFront(const ParticleSet& ps, double spacing, std::vector<double>& scratch) {
  scratch.assign(ps.position.size(), 0);
  for (size_t i = 0; i < ps.size(); ++i) scratch[i] = ps.position[i].x;
  const size_t k = size_t(std::floor(0.999 * double(scratch.size() - 1)));
  std::nth_element(scratch.begin(), scratch.begin() + long(k), scratch.end());
  return scratch[k] + 0.5 * spacing;
}

// Height of the column at the back wall: the top of the particles in the first layer there.
double backWallHeight(const ParticleSet& ps, double spacing) {
  double top = 0;
  for (size_t i = 0; i < ps.size(); ++i)
    if (ps.position[i].x < spacing) top = std::max(top, ps.position[i].y);
  return top + 0.5 * spacing;
}

Measured runDamBreak(const Setting& s) {
  const double omega = std::sqrt(2 * kG / kA);  // T = omega t
  std::vector<std::string> sets = dtOverrides(s.dtFactor);
  sets.push_back("solver.particle_spacing=" + tomlReal(s.spacing));
  sets.push_back("scene.end_time=" + tomlReal(kTMax / omega));
  const Scene scene = loadScene("dam_break", sets);
  std::vector<std::pair<double, double>> front, height;  // (t, x/a), (t, h/2a)
  std::vector<double> scratch;
  Measured m = runCase(scene, [&](Simulation& sim, Stopwatch& sw) {
    auto record = [&](const Simulation& x) {
      sw.exclude([&] {
        front.emplace_back(x.time(), surgeFront(x.particles(), s.spacing, scratch) / kA);
        height.emplace_back(x.time(), backWallHeight(x.particles(), s.spacing) / (2 * kA));
      });
    };
    record(sim);
    sim.advanceTo(scene.endTime, record);
  });
  if (m.status != "ok") return m;
  const double tau = std::sqrt(kG / kA);  // Table 6's time scale (no factor n)
  auto Z = [&](double T) { return interpolate(front, T / omega); };
  auto H = [&](double ta) { return interpolate(height, ta / tau); };
  const double tauMax = kTMax / std::sqrt(2.0), shiftTau = kShiftT / std::sqrt(2.0);
  m.error = rmsAgainst(kSurgeFront, kTMax, 0, Z);
  m.extras = {rmsAgainst(kSurgeFront, kTMax, kShiftT, Z), rmsAgainst(kColumnHeight, tauMax, 0, H),
              rmsAgainst(kColumnHeight, tauMax, shiftTau, H)};
  for (const auto& [t, z] : front) m.curve.emplace_back(omega * t, z);
  return m;
}

// ---- hydrostatic column ----------------------------------------------------------------------

constexpr double kSettle = 0.3, kAverageUntil = 0.6, kColumnDepth = 0.14, kColumnWidth = 0.1;

// The column of tests/test_hydrostatic.cpp, 0.14 m deep so that a 1 cm spacing still leaves
// interior depth bins; damping relaxes the start's acoustic ringing until kSettle.
Scene hydrostaticScene(const Setting& s) {
  const std::string text = fmt::format(R"(
[scene]
name = "hydrostatic"
end_time = {end}
frame_rate = 10
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.21, 0.11]
[solver]
particle_spacing = {s}
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.5
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [{w}, 0.2, {w}]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [{w}, {depth}, {w}]
[effects.gravity]
[effects.pressure]
gradient_correction = {grad}
[effects.viscosity]
[effects.damping]
rate = 40.0
until = {settle}
)",
                                       fmt::arg("end", tomlReal(kAverageUntil)), fmt::arg("s", tomlReal(s.spacing)),
                                       fmt::arg("w", tomlReal(kColumnWidth)), fmt::arg("depth", tomlReal(kColumnDepth)),
                                       fmt::arg("grad", s.variant == "corrected" ? "1.0" : "0.0"),
                                       fmt::arg("settle", tomlReal(kSettle)));
  return parseScene(text, "<report:hydrostatic>", dtOverrides(s.dtFactor));
}

// As in the test: time average over every sub-step after settling, per depth bin one support
// radius tall, of the interior particles' pressure against rho0 g (H - y), where H comes from
// the mass (the weight above y is what p(y) carries). Bins within two support radii of the floor
// or of the free surface are left out: there the density sum is cut off by design of SPH.
Measured runHydrostatic(const Setting& s) {
  const Scene scene = hydrostaticScene(s);
  const double rho0 = 1000, w = kColumnWidth;
  struct BinSums {
    double p = 0, expected = 0, weight = 0;  // sums of dt p, dt rho0 g (H - y), dt
  };
  std::map<int, BinSums> bins;
  double H = 0, h = 0;
  Measured m = runCase(scene, [&](Simulation& sim, Stopwatch& sw) {
    h = sim.kernels().h;
    double mass = 0;
    for (double mi : sim.particles().mass) mass += mi;
    H = mass / (rho0 * w * w);
    sim.advanceTo(kSettle);
    sim.advanceTo(kAverageUntil, [&](const Simulation& x) {
      sw.exclude([&] {
        const ParticleSet& ps = x.particles();
        const double dt = x.counters().lastDt;
        for (size_t i = 0; i < ps.size(); ++i) {
          const Vec3 p = ps.position[i];
          if (p.x < h || p.x > w - h || p.z < h || p.z > w - h) continue;
          auto& b = bins[int(std::floor(p.y / h))];
          b.p += dt * ps.pressure[i];
          b.expected += dt * rho0 * kG * (H - p.y);
          b.weight += dt;
        }
      });
    });
  });
  if (m.status != "ok") return m;
  double sum = 0, worst = 0;
  int n = 0;
  for (const auto& [bin, sums] : bins) {
    if (bin * h < 2 * h - 1e-9 || (bin + 1) * h > H - 2 * h) continue;
    // Normalised by the bottom pressure: relative to the local pressure, the bins nearest the
    // surface (included only at fine spacings) would dominate and hide the convergence.
    const double e = (sums.p - sums.expected) / sums.weight / (rho0 * kG * H);
    sum += e * e;
    worst = std::max(worst, std::fabs(sums.p / sums.expected - 1));
    ++n;
  }
  m.error = n > 0 ? std::sqrt(sum / n) : kNaN;
  m.extras = {worst, double(n)};
  if (n == 0) m.status = "no interior depth bin at this spacing";
  return m;
}

// ---- heat diffusion across a plane -----------------------------------------------------------

constexpr double kAlpha = 1e-3, kHeatTime = 1.0;

// tests/test_interaction.cpp's slab: 0 degrees beside 1 degree, particles at rest, only heat
// moves. The cross-section is at least 8 spacings so that interior particles exist at any
// spacing. cfl = 10 with k = 1: the diffusion limit alone sets dt, scaled by the factor.
Scene heatScene(const Setting& s) {
  const double width = std::max(0.06, 8 * s.spacing);
  const std::string text = fmt::format(R"(
[scene]
name = "heat_diffusion"
end_time = {end}
domain_min = [-1.0, -1.0, -1.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
particle_spacing = {s}
max_dt = 1.0
cfl = 10.0
[[phase]]
name = "a"
rest_density = 1000.0
stiffness = 1.0
thermal_diffusivity = {alpha}
[[fluid]]
phase = "a"
min = [-0.2, 0.0, 0.0]
max = [0.0, {w}, {w}]
temperature = 0.0
[[fluid]]
phase = "a"
min = [0.0, 0.0, 0.0]
max = [0.2, {w}, {w}]
temperature = 1.0
[effects.heat_diffusion]
stability_factor = {factor}
)",
                                       fmt::arg("end", tomlReal(kHeatTime)), fmt::arg("s", tomlReal(s.spacing)),
                                       fmt::arg("alpha", tomlReal(kAlpha)), fmt::arg("w", tomlReal(width)),
                                       fmt::arg("factor", tomlReal(std::min(1.0, 0.5 * s.dtFactor))));
  return parseScene(text, "<report:heat_diffusion>");
}

// RMS of T - (1 + erf(x / 2 sqrt(alpha t)))/2 over particles one support radius inside the slab's
// insulating faces and within 0.15 m of the plane (the erf solution is for an infinite medium).
Measured runHeat(const Setting& s) {
  const Scene scene = heatScene(s);
  const double width = std::max(0.06, 8 * s.spacing);
  double sum = 0, worst = 0;
  int n = 0;
  Measured m = runCase(scene, [&](Simulation& sim, Stopwatch& sw) {
    sim.advanceTo(kHeatTime);
    sw.exclude([&] {
      const ParticleSet& ps = sim.particles();
      const double h = sim.kernels().h;
      for (size_t i = 0; i < ps.size(); ++i) {
        const Vec3 x = ps.position[i];
        if (x.y < h || x.y > width - h || x.z < h || x.z > width - h || std::fabs(x.x) > 0.15) continue;
        const double e = ps.temperature[i] - 0.5 * (1 + std::erf(x.x / (2 * std::sqrt(kAlpha * kHeatTime))));
        sum += e * e;
        worst = std::max(worst, std::fabs(e));
        ++n;
      }
    });
  });
  if (m.status != "ok") return m;
  m.error = std::sqrt(sum / n);
  m.extras = {worst};
  return m;
}

// ---- two fluids layered ----------------------------------------------------------------------

constexpr double kLayerTime = 4.0, kLayer = 0.06;

// Rayleigh-Taylor: the heavy fluid (1000 kg/m^3) starts above the light one (500 kg/m^3), both
// jittered by 0.1 spacing (seeded) so that the overturn does not wait on rounding noise; viscosity
// and stiffness as in configs/two_fluids_mixed.toml.
Scene layeredScene(const Setting& s) {
  const std::string text = fmt::format(R"(
[scene]
name = "layered"
end_time = {end}
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.21, 0.07]
[solver]
particle_spacing = {s}
density_formulation = "{formulation}"
max_dt = 0.002
[[phase]]
name = "light"
rest_density = 500.0
stiffness = 200.0
viscosity = 0.5
[[phase]]
name = "heavy"
rest_density = 1000.0
stiffness = 200.0
viscosity = 0.5
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.2, 0.06]
[[fluid]]
phase = "light"
min = [0.0, 0.0, 0.0]
max = [0.1, {layer}, 0.06]
jitter = 0.1
seed = 1
[[fluid]]
phase = "heavy"
min = [0.0, {layer}, 0.0]
max = [0.1, {top}, 0.06]
jitter = 0.1
seed = 2
[effects.gravity]
[effects.pressure]
[effects.viscosity]
)",
                                       fmt::arg("end", tomlReal(kLayerTime)), fmt::arg("s", tomlReal(s.spacing)),
                                       fmt::arg("formulation", s.variant), fmt::arg("layer", tomlReal(kLayer)),
                                       fmt::arg("top", tomlReal(2 * kLayer)));
  return parseScene(text, "<report:layered>", dtOverrides(s.dtFactor));
}

// The settled interface lies where as many particles are below it as there are heavy ones (a
// level that compression does not move). A heavy particle more than half a spacing above it, or
// a light one more than half a spacing below, is on the wrong side. Error: their mass over the
// total; extras: the fraction of each fluid's own mass.
struct WrongSide {
  double heavy = 0, light = 0, total = 0;  // kg on the wrong side; total fluid mass
  double heavyMass = 0, lightMass = 0;
};

WrongSide wrongSide(const ParticleSet& ps, int heavy, double spacing) {
  std::vector<double> y(ps.position.size());
  size_t nHeavy = 0;
  WrongSide w;
  for (size_t i = 0; i < ps.size(); ++i) {
    y[i] = ps.position[i].y;
    nHeavy += ps.phase[i] == heavy;
    (ps.phase[i] == heavy ? w.heavyMass : w.lightMass) += ps.mass[i];
  }
  w.total = w.heavyMass + w.lightMass;
  if (nHeavy == 0 || nHeavy == y.size()) return w;
  std::sort(y.begin(), y.end());
  const double level = 0.5 * (y[nHeavy - 1] + y[nHeavy]);
  for (size_t i = 0; i < ps.size(); ++i) {
    const double yi = ps.position[i].y;
    if (ps.phase[i] == heavy && yi > level + 0.5 * spacing) w.heavy += ps.mass[i];
    if (ps.phase[i] != heavy && yi < level - 0.5 * spacing) w.light += ps.mass[i];
  }
  return w;
}

Measured runLayered(const Setting& s) {
  const Scene scene = layeredScene(s);
  WrongSide w;
  Measured m = runCase(scene, [&](Simulation& sim, Stopwatch& sw) {
    sim.advanceTo(kLayerTime);
    sw.exclude([&] { w = wrongSide(sim.particles(), scene.phaseIndex("heavy"), s.spacing); });
  });
  if (m.status != "ok") return m;
  m.error = (w.heavy + w.light) / w.total;
  m.extras = {w.heavy / w.heavyMass, w.light / w.lightMass};
  return m;
}

// ---- the ladders ------------------------------------------------------------------------------

Setting rung(double spacing, double f, std::string variant, const std::string& spacingName) {
  Setting s{spacing, f, std::move(variant), ""};
  s.label = fmt::format("{} f={}{}", spacingName, f, s.variant.empty() ? "" : " " + s.variant);
  return s;
}

std::string mm(double spacing) { return fmt::format("{:.3g}mm", spacing * 1000); }

std::vector<Problem> problems(bool quick) {
  std::vector<Problem> list;
  {
    Problem p{"dam_break", "Dam break against Martin & Moyce (1952)", "RMS error of Z = x/a",
              "RMS over the 13 points of Table 2 with T <= 3 of Z_sim(T) - Z_exp(T), Z = x/a, T = t sqrt(2g/a); "
              "x = the 99.9th percentile of particle x plus half a spacing, measured from the back wall",
              "The embedded scene `dam_break` (a = 2.25 in = 0.05715 m, a column a x 2a x a in a tank 5a x 3a x a, "
              "k = 400 m^2/s^2, mu = 0.05 Pa s) with `solver.particle_spacing = a/n` and the time-step factor f, "
              "run to T = 3.",
              {"rms_Z_shifted", "rms_H", "rms_H_shifted"}, {}, runDamBreak, 0,
              "RMS error of Z, time shifted by 0.175"};
    auto add = [&](int n, double f) { p.ladder.push_back(rung(kA / n, f, "", fmt::format("a/{}", n))); };
    if (quick) {
      add(8, 1), add(8, 2);
    } else {
      for (int n : {8, 12, 16, 24, 32}) add(n, 1);
      for (int n : {8, 16, 24, 32}) add(n, 2);
      add(16, 0.5);
    }
    list.push_back(p);
  }
  {
    Problem p{"hydrostatic", "Hydrostatic column", "RMS pressure error / rho0 g H",
              "RMS over interior depth bins (one support radius tall, two support radii clear of floor and surface, "
              "one clear of the side walls) of (p_avg - (rho0 g (H - y))_avg) / (rho0 g H), time-averaged over every "
              "step of 0.3 s .. 0.6 s; `max_bin_ratio_error` is the largest |p_avg / (rho0 g (H - y))_avg - 1| (the "
              "measure of tests/test_hydrostatic.cpp, which grows towards the surface)",
              "A water column 0.1 x 0.14 x 0.1 m (rho0 = 1000, k = 1000, mu = 0.5 Pa s) in a box, damped "
              "(40/s) until 0.3 s; variants: plain kernel gradient, or `gradient_correction = 1`.",
              {"max_bin_ratio_error", "bins"}, {}, runHydrostatic, -1, ""};
    auto add = [&](double s, double f, const char* v) { p.ladder.push_back(rung(s, f, v, mm(s))); };
    if (quick) {
      add(0.01, 1, "plain"), add(0.01, 1, "corrected");
    } else {
      for (double s : {0.01, 0.02 / 3, 0.005})
        for (const char* v : {"plain", "corrected"}) add(s, 1, v);
      for (const char* v : {"plain", "corrected"}) add(0.005, 2, v);
    }
    list.push_back(p);
  }
  {
    Problem p{"heat_diffusion", "Heat diffusion across a plane against erf", "RMS temperature error (unit step)",
              "RMS over interior particles within 0.15 m of the plane of T - (1 + erf(x / (2 sqrt(alpha t))))/2 "
              "at t = 1 s",
              "Two slabs at 0 and 1 degree side by side (0.2 m each, cross-section max(6 cm, 8 spacings)), "
              "alpha = 1e-3 m^2/s, particles at rest; f scales the diffusion stability factor (0.5 f, at most 1).",
              {"max_abs_error"}, {}, runHeat, -1, ""};
    auto add = [&](double s, double f) { p.ladder.push_back(rung(s, f, "", mm(s))); };
    if (quick) {
      add(0.02, 1), add(0.01, 1);
    } else {
      for (double s : {0.02, 0.01, 0.02 / 3, 0.005, 0.004}) add(s, 1);
      for (double s : {0.01, 0.005}) add(s, 2), add(s, 0.25);
    }
    list.push_back(p);
  }
  {
    Problem p{"layered", "Two fluids layered (Rayleigh-Taylor overturn)", "mass on the wrong side / total mass",
              "after 4 s (measured at 1 cm: 6 % at 2 s, 1.4 % at 4 s, 1.0 % at 6 s): the interface is the level with as many particles below it as there are heavy ones; "
              "heavy mass more than half a spacing above it plus light mass more than half a spacing below it, "
              "over the total mass",
              "Heavy fluid (1000 kg/m^3) above light (500 kg/m^3), 6 cm each in a 0.1 x 0.2 x 0.06 m box, "
              "k = 200, mu = 0.5 Pa s, jitter 0.1 spacing; variants: `density_formulation` mass (eq. 1) or number.",
              {"heavy_wrong_fraction", "light_wrong_fraction"}, {}, runLayered, -1, ""};
    auto add = [&](double s, double f, const char* v) { p.ladder.push_back(rung(s, f, v, mm(s))); };
    if (quick) {
      add(0.01, 1, "mass"), add(0.01, 1, "number");
    } else {
      for (double s : {0.01, 0.02 / 3, 0.005})
        for (const char* v : {"mass", "number"}) add(s, 1, v);
      for (const char* v : {"mass", "number"}) add(0.005, 2, v);
    }
    list.push_back(p);
  }
  return list;
}

// ---- output --------------------------------------------------------------------------------

std::vector<bool> frontOf(const Problem& p, const std::vector<Measured>& r, bool alt) {
  std::vector<double> walls, errors;
  for (const auto& m : r) walls.push_back(m.wall), errors.push_back(p.errorOf(m, alt));
  return paretoFront(walls, errors);
}

// Columns `pareto` and `status` come last (the CI check reads them there).
Table resultTable(const Problem& p, const std::vector<Measured>& results) {
  const std::vector<bool> front = frontOf(p, results, false), altFront = frontOf(p, results, true);
  Table t;
  t.header = {"problem", "setting", "spacing_m", "dt_factor", "variant", "particles", "steps", "wall_s", "cpu_s", "load_1min", "error"};
  for (const auto& e : p.extraColumns) t.header.push_back(e);
  if (p.altExtra >= 0) t.header.push_back("pareto_" + p.extraColumns[size_t(p.altExtra)]);
  t.header.push_back("pareto");
  t.header.push_back("status");
  for (size_t k = 0; k < results.size(); ++k) {
    const Setting& s = p.ladder[k];
    const Measured& m = results[k];
    std::vector<std::string> row = {p.name, s.label, fmtNumber(s.spacing, 6), fmtNumber(s.dtFactor), s.variant,
                                    std::to_string(m.particles), std::to_string(m.steps), fmt::format("{:.3f}", m.wall),
                                    fmt::format("{:.3f}", m.cpu), fmt::format("{:.2f}", m.load), fmtNumber(m.error, 4)};
    for (size_t e = 0; e < p.extraColumns.size(); ++e) row.push_back(e < m.extras.size() ? fmtNumber(m.extras[e], 4) : "-");
    if (p.altExtra >= 0) row.push_back(altFront[k] ? "1" : "0");
    row.push_back(front[k] ? "1" : "0");
    row.push_back(m.status);
    t.add(row);
  }
  return t;
}

// Gnuplot data block of (wall, error, label) of the settings with an error, by wall time;
// `onlyFront` keeps the Pareto points (joined by a line in the plot).
std::string dataBlock(const std::string& name, const Problem& p, const std::vector<Measured>& r, bool alt, bool onlyFront) {
  const std::vector<bool> front = frontOf(p, r, alt);
  std::vector<size_t> order;
  for (size_t k = 0; k < r.size(); ++k)
    if (std::isfinite(p.errorOf(r[k], alt)) && p.errorOf(r[k], alt) > 0 && (!onlyFront || front[k])) order.push_back(k);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return r[a].wall < r[b].wall; });
  std::string out = "$" + name + " << EOD\n";
  for (size_t k : order)
    out += fmt::format("{:.6g} {:.6g} \"{}\"\n", r[k].wall, p.errorOf(r[k], alt), escapeGnuplot(p.ladder[k].label));
  return out + "EOD\n";
}

// Error (log) against wall time (log), every setting labelled, the Pareto front joined; a
// problem with a second error gets its points and front in blue.
std::string paretoScript(const Problem& p, const std::vector<Measured>& r, const Machine& machine) {
  std::string data = dataBlock("all", p, r, false, false) + dataBlock("front", p, r, false, true);
  std::string plots = fmt::format(
      "$all using 1:2 with points pt 7 ps 1.3 lc rgb \"#7f7f7f\" title \"{}\", \\\n"
      "     $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb \"#d62728\" title \"Pareto front\", \\\n"
      "     $all using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font \"sans,8\" notitle",
      escapeGnuplot(p.errorName));
  if (p.altExtra >= 0) {
    data += dataBlock("alt", p, r, true, false) + dataBlock("altfront", p, r, true, true);
    plots += fmt::format(
        ", \\\n     $alt using 1:2 with points pt 5 ps 1.1 lc rgb \"#1f77b4\" title \"{}\", \\\n"
        "     $altfront using 1:2 with linespoints lw 2 pt 4 ps 2.0 lc rgb \"#1f77b4\" dt 2 title \"its Pareto front\", \\\n"
        "     $alt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font \"sans,8\" tc rgb \"#1f77b4\" notitle",
        escapeGnuplot(p.altName));
  }
  return fmt::format(R"gp(set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "accuracy_{name}.png.tmp"
{data}set logscale xy
set grid
set title "{title}"
set xlabel "wall time (s), {machine}"
set ylabel "{error} (log)"
set key top right
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot {plots}
)gp",
                     fmt::arg("name", p.name), fmt::arg("data", data), fmt::arg("plots", plots),
                     fmt::arg("title", escapeGnuplot(p.title)), fmt::arg("machine", escapeGnuplot(machine.cpuModel)),
                     fmt::arg("error", escapeGnuplot(p.errorName)));
}

// Z(T) of every dam-break setting over the experiment's points.
std::string frontScript(const Problem& p, const std::vector<Measured>& r) {
  std::string data, plots;
  for (size_t k = 0; k < r.size(); ++k) {
    if (r[k].curve.empty()) continue;
    data += fmt::format("$s{} << EOD\n", k);
    // Thinned to about 200 points per curve: the plot needs no more.
    const size_t stride = std::max<size_t>(1, r[k].curve.size() / 200);
    for (size_t i = 0; i < r[k].curve.size(); i += stride)
      data += fmt::format("{:.5g} {:.5g}\n", r[k].curve[i].first, r[k].curve[i].second);
    data += "EOD\n";
    plots += fmt::format("$s{} using 1:2 with lines lw 1.5 title \"{}\", \\\n     ", k, escapeGnuplot(p.ladder[k].label));
  }
  std::string exp = "$exp << EOD\n";
  for (const auto& [T, Z] : kSurgeFront) exp += fmt::format("{} {}\n", T, Z);
  exp += "EOD\n";
  return fmt::format(R"gp(set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "dam_break_front.png.tmp"
{data}{exp}set grid
set title "Dam break surge front: simulation against Martin & Moyce (1952), Table 2 (no time shift)"
set xlabel "T = t sqrt(2g/a)"
set ylabel "Z = x/a"
set xrange [0:3.4]
set key top left
plot {plots}$exp using 1:2 with points pt 7 ps 1.5 lc rgb "black" title "Martin & Moyce 1952, Table 2"
)gp",
                     fmt::arg("data", data), fmt::arg("exp", exp), fmt::arg("plots", plots));
}

// For each budget, the lowest-error setting that ran within it.
std::string budgetTable(const Problem& p, const std::vector<Measured>& r, bool alt) {
  std::string out = "| time budget | best setting | error | wall time |\n|---|---|---|---|\n";
  double maxWall = 0;
  for (const auto& m : r) maxWall = std::max(maxWall, m.wall);
  for (double budget : {0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0}) {
    int best = -1;
    for (size_t k = 0; k < r.size(); ++k) {
      const double e = p.errorOf(r[k], alt);
      if (r[k].wall <= budget && std::isfinite(e) && (best < 0 || e < p.errorOf(r[size_t(best)], alt))) best = int(k);
    }
    if (best < 0) continue;
    out += fmt::format("| {} s | {} | {} | {:.2f} s |\n", budget, p.ladder[size_t(best)].label,
                       fmtNumber(p.errorOf(r[size_t(best)], alt), 3), r[size_t(best)].wall);
    if (budget >= maxWall) break;  // every setting fits: larger budgets say nothing new
  }
  return out;
}

std::string shiftNote() {
  return fmt::format(
      "Time shift: the gate in the experiment did not open instantly. Columns `rms_Z_shifted` and "
      "`rms_H_shifted` compare the simulation delayed by dT = {} (Z_sim(T - {}) against Z_exp(T); the "
      "value Lethe's Martin-Moyce example uses, taken from there, not fitted here); `error` and `rms_H` "
      "use no shift. `rms_H` is the residual column height at the back wall, H = h/(2a) against Table 6 "
      "(tau = t sqrt(g/a) <= {:.2f}), a second check not used for the front.\n",
      kShiftT, kShiftT, kTMax / std::sqrt(2.0));
}

std::string frontCsv(const Problem& p, const std::vector<Measured>& r) {
  std::string out = "setting,T,Z\n";
  for (size_t k = 0; k < r.size(); ++k)
    for (const auto& [T, Z] : r[k].curve) out += fmt::format("{},{:.5g},{:.5g}\n", p.ladder[k].label, T, Z);
  return out;
}

struct RunInfo {
  std::string commandLine, date, machine, loadStart, loadEnd, ladder;
  double seconds = 0;
};

// One problem's part of the page, saved on its own so that `--only NAME` can re-run one problem
// and the page is put together again from every problem's latest part.
std::string section(const Problem& p, Table t, const std::vector<Measured>& r, const RunInfo& info) {
  std::string out = fmt::format("## {}: {}\n\n*Measured by `{}` on {}, {} ladder, in {}. Machine: {}; load average "
                                "{} at the start, {} at the end.*\n\n{}\n\n**Error**: {}.\n\n",
                                p.name, p.title, info.commandLine, info.date, info.ladder, formatDuration(info.seconds),
                                info.machine, info.loadStart, info.loadEnd, p.method, p.errorDefinition);
  if (p.altExtra >= 0) out += shiftNote() + "\n";
  out += fmt::format("![error against wall time](accuracy_{}.png)\n\n", p.name);
  std::vector<std::string> cols = {"setting", "particles", "steps", "wall_s", "cpu_s", "load_1min", "error"};
  for (const auto& e : p.extraColumns) cols.push_back(e);
  for (size_t c = 0; c < t.header.size(); ++c)
    if (t.header[c].rfind("pareto", 0) == 0) {
      cols.push_back(t.header[c]);
      for (auto& row : t.rows) row[c] = row[c] == "1" ? "**yes**" : "";
    }
  const bool anyFailed = std::any_of(r.begin(), r.end(), [](const Measured& m) { return m.status != "ok"; });
  if (anyFailed) cols.push_back("status");
  out += t.markdown(cols) + "\n";
  out += "Best setting for a time budget (the lowest error among the settings that ran within it, on this "
         "machine):\n\n" + budgetTable(p, r, false) + "\n";
  if (p.altExtra >= 0)
    out += fmt::format("The same by {}:\n\n{}\n", p.altName, budgetTable(p, r, true));
  if (p.name == "dam_break") out += "![surge front against the experiment](dam_break_front.png)\n\n";
  return out;
}

std::string pageHeader() {
  return "# Accuracy against run time\n\n"
         "Each problem below runs a ladder of settings, one at a time in one process, on the machine its "
         "section names. `wall_s` covers building the simulation and stepping it, not the report's own "
         "measurements; `cpu_s` is the CPU time of all threads over the same span and `load_1min` the machine's "
         "1-minute load average after the setting: where the load exceeds the core count, other work competed "
         "for the cores and the wall time is inflated.\n\n"
         "The time-step factor f scales the time-step criteria: `solver.cfl` = 0.4 f and "
         "`solver.force_factor` = 0.25 f (heat diffusion: its `stability_factor` = 0.5 f, at most 1). Every "
         "setting is a scene-file value; nothing is fitted to the reference data. A setting the watchdog stopped "
         "has no error and is left out of the Pareto front, which holds the settings that no other setting beats "
         "in both wall time and error.\n\n";
}

// The page: the header and every problem's latest section found in the folder, in ladder order.
std::string assemblePage(const fs::path& out) {
  std::string page = pageHeader();
  for (const auto& p : problems(false)) {
    const fs::path part = out / ("accuracy_" + p.name + ".md");
    if (!fs::exists(part)) continue;
    std::ifstream in(part);
    page += std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return page;
}

}  // namespace

int runAccuracy(const Options& opt, const Machine& machine) {
  const auto start = Clock::now();
  std::vector<Problem> list;
  for (auto& p : problems(opt.quick))
    if (opt.selected(p.name)) list.push_back(std::move(p));
  if (list.empty()) return 0;
  size_t total = 0, done = 0;
  for (const auto& p : list) total += p.ladder.size();
  const fs::path out(opt.out);
  bool plotsOk = true;
  for (const Problem& p : list) {
    const auto problemStart = Clock::now();
    RunInfo info{opt.commandLine, utcNow(), machine.describe(), loadAverage(), "", opt.quick ? "quick (CI check)" : "full"};
    std::vector<Measured> results;
    for (const Setting& s : p.ladder) {
      results.push_back(p.run(s));
      const Measured& m = results.back();
      fmt::print(stderr, "[accuracy {}/{}] {} {}: {} particles, {} steps, {:.2f} s, error {}{}  (elapsed {})\n", ++done,
                 total, p.name, s.label, m.particles, m.steps, m.wall, fmtNumber(m.error, 4),
                 m.status == "ok" ? "" : " [" + m.status + "]", formatDuration(secondsSince(start)));
    }
    info.loadEnd = loadAverage();
    info.seconds = secondsSince(problemStart);
    const Table t = resultTable(p, results);
    writeText((out / ("accuracy_" + p.name + ".csv")).string(), t.csv());
    plotsOk &= plot(opt, "accuracy_" + p.name, paretoScript(p, results, machine),
                    (out / ("accuracy_" + p.name + ".png")).string());
    if (p.name == "dam_break") {
      writeText((out / "dam_break_front.csv").string(), frontCsv(p, results));
      plotsOk &= plot(opt, "dam_break_front", frontScript(p, results), (out / "dam_break_front.png").string());
    }
    writeText((out / ("accuracy_" + p.name + ".md")).string(), section(p, t, results, info));
  }
  writeText((out / "accuracy.md").string(), assemblePage(out));
  fmt::print(stderr, "report accuracy: {} settings in {} on {}; wrote {}\n", total, formatDuration(secondsSince(start)),
             machine.describe(), (out / "accuracy.md").string());
  return plotsOk ? 0 : 4;
}

}  // namespace mf::report
