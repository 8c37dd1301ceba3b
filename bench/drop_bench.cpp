// drop_bench: surface tension against its two textbook answers (issue 21), for both pressure
// solvers, on a water drop in zero gravity at 1 cm spacing (sigma = 1 N/m):
//  - static drops of several radii: the mean pressure inside half the radius, averaged over the
//    steps of the second half of the run, against Laplace's 2 sigma / R; and the tension force on
//    the upper half of the drop (its y component summed over the particles above the centroid)
//    against 2 pi R sigma, the pull of the surface along the equator, which balances it (DFSPH
//    only: under WCSPH the pressure is among the forces);
//  - a drop stretched into a spheroid (semi-axes R(1+e), R/sqrt(1+e)): the period of its n = 2
//    oscillation, from the zero crossings of sum (x^2 - y^2), against Rayleigh's
//    2 pi / sqrt(8 sigma / (rho R^3)).
// R is the radius of the drop's volume, (3 N s^3 / 4 pi)^(1/3).
//
//   drop_bench [--solvers dfsph,wcsph] [--radii 0.035,0.05,0.08] [--end 1] [--period-radius 0.05]
//              [--trace] [--set key=value]...      (--trace: the n = 2 drop's sum every 0.02 s)
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

using namespace mf;

constexpr Real kSigma = 1.0, kRho = 1000.0, kSpacing = 0.01;

std::string dropScene(const std::string& solver, Real R, Real stretch, Real endTime) {
  const Real a = R * (1 + stretch), b = R / std::sqrt(1 + stretch);
  return fmt::format(R"([scene]
name = "drop"
end_time = {end}
domain_min = [-0.5, -0.5, -0.5]
domain_max = [0.5, 0.5, 0.5]
[solver]
particle_spacing = {s}
max_dt = 0.005
pressure = "{solver}"
[[phase]]
name = "water"
rest_density = {rho}
stiffness = 100.0
viscosity = 0.01
surface_tension = {sigma}
[[fluid]]
phase = "water"
shape = "ellipsoid"
centre = [0.0, 0.0, 0.0]
radii = [{a}, {b}, {b}]
[effects.pressure]
[effects.viscosity]
[effects.surface_tension]
)",
                     fmt::arg("end", endTime), fmt::arg("s", kSpacing), fmt::arg("solver", solver), fmt::arg("rho", kRho),
                     fmt::arg("sigma", kSigma), fmt::arg("a", a), fmt::arg("b", b));
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) v.push_back(item);
  return v;
}

Vec3 centroid(const ParticleSet& q) {
  Vec3 c;
  for (const Vec3& x : q.position) c += x;
  return c * (1.0 / Real(q.size()));
}

void staticDrop(const std::string& solver, Real R0, Real end, const std::vector<std::string>& sets) {
  Simulation sim(parseScene(dropScene(solver, R0, 0, end), "drop.toml", sets));
  const Real R = std::cbrt(3 * Real(sim.particles().size()) * kSpacing * kSpacing * kSpacing / (4 * kPi));
  Real pressure = 0, cap = 0;
  int samples = 0;
  sim.advanceTo(end, [&](const Simulation& s) {
    if (s.time() <= 0.5 * end) return;
    const ParticleSet& q = s.particles();
    const Vec3 c = centroid(q);
    Real sum = 0, up = 0;
    int count = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      const Vec3 d = q.position[i] - c;
      if (length(d) < 0.5 * R) sum += q.mechanicalPressure(i), ++count;
      if (d.y > 0) up += q.force[i].y;  // the non-pressure forces of the step: tension (and viscosity)
    }
    if (count) pressure += sum / count, cap += up, ++samples;
  });
  pressure /= samples, cap /= samples;
  const Real laplace = 2 * kSigma / R, line = 2 * kPi * R * kSigma;
  // WCSPH's pressure is one of the forces, so the upper half's force is the tension's only on DFSPH.
  const std::string tension = solver == "dfsph" ? fmt::format("; upper-half tension {:.4f} N, 2 pi R sigma = {:.4f} N, ratio {:.3f}",
                                                              -cap, line, -cap / line)
                                                : std::string();
  fmt::print("{:<6} static R = {:.4f} m ({:5} particles, {:4} steps): interior p = {:6.2f} Pa, 2 sigma/R = {:6.2f} Pa, ratio {:.3f}{}\n",
             solver, R, sim.particles().size(), sim.counters().steps, pressure, laplace, pressure / laplace, tension);
}

void oscillatingDrop(const std::string& solver, Real R0, const std::vector<std::string>& sets, bool trace) {
  const Real stretch = 0.2;
  const Real guess = 2 * kPi / std::sqrt(8 * kSigma / (kRho * R0 * R0 * R0));
  const Real end = 2.5 * guess;
  Simulation sim(parseScene(dropScene(solver, R0, stretch, end), "drop.toml", sets));
  const Real R = std::cbrt(3 * Real(sim.particles().size()) * kSpacing * kSpacing * kSpacing / (4 * kPi));
  const Real rayleigh = 2 * kPi / std::sqrt(8 * kSigma / (kRho * R * R * R));
  std::vector<Real> crossings;
  Real last = 0, lastT = 0;
  sim.advanceTo(end, [&](const Simulation& s) {
    const ParticleSet& q = s.particles();
    const Vec3 c = centroid(q);
    Real m = 0;
    for (const Vec3& x : q.position) m += (x.x - c.x) * (x.x - c.x) - (x.y - c.y) * (x.y - c.y);
    const Real t = s.time();
    if (lastT > 0 && (m > 0) != (last > 0)) crossings.push_back(lastT + (t - lastT) * last / (last - m));
    if (trace && std::floor(t / 0.02) != std::floor(lastT / 0.02)) fmt::print("  t {:.3f} s  sum(x^2 - y^2) {:+.4e} m^2\n", t, m);
    last = m, lastT = t;
  });
  std::string line = fmt::format("{:<6} n = 2  R = {:.4f} m ({:5} particles, {:4} steps): ", solver, R, sim.particles().size(),
                                 sim.counters().steps);
  if (crossings.size() < 3) {
    fmt::print("{}{} zero crossings in {:.2f} s: no oscillation (Rayleigh's period {:.3f} s)\n", line, crossings.size(), end, rayleigh);
    return;
  }
  // Crossings 1 apart are half a period apart; the first one is left out (the start).
  const Real period = 2 * (crossings.back() - crossings[1]) / Real(crossings.size() - 2);
  fmt::print("{}period {:.3f} s from {} crossings, Rayleigh {:.3f} s, ratio {:.3f}\n", line, period, crossings.size(), rayleigh,
             period / rayleigh);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> solvers = {"dfsph", "wcsph"}, radii = {"0.035", "0.05", "0.08"}, sets;
  Real end = 1, periodRadius = 0.05;
  bool trace = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--solvers" && more) solvers = split(argv[++i]);
    else if (a == "--radii" && more) radii = split(argv[++i]);
    else if (a == "--end" && more) end = std::stod(argv[++i]);
    else if (a == "--period-radius" && more) periodRadius = std::stod(argv[++i]);
    else if (a == "--set" && more) sets.push_back(argv[++i]);
    else if (a == "--trace") trace = true;
    else {
      fmt::print(stderr, "usage: drop_bench [--solvers dfsph,wcsph] [--radii 0.035,0.05,0.08] [--end 1] [--period-radius 0.05] [--trace] [--set key=value]...\n");
      return 2;
    }
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  try {
    for (const std::string& s : solvers) {
      for (const std::string& r : radii) staticDrop(s, std::stod(r), end, sets);
      if (periodRadius > 0) oscillatingDrop(s, periodRadius, sets, trace);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "drop_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
