// drop_bench: surface tension against its two textbook answers (issue 21), for both pressure
// solvers, on a water drop in zero gravity at 1 cm spacing (sigma = 1 N/m):
//  - static drops of several radii: the mean pressure inside half the radius, averaged over the
//    steps of the second half of the run, against Laplace's 2 sigma / R; and the tension force on
//    the upper half of the drop (its y component summed over the particles above the centroid)
//    against 2 pi R sigma, the pull of the surface along the equator, which balances it (DFSPH
//    only: under WCSPH the pressure is among the forces);
//  - the period of a drop's n = 2 oscillation, started by the mode's own potential flow once the
//    drop has rested (--relax seconds), against Rayleigh's 2 pi / sqrt(8 sigma / (rho R^3)).
// R is the radius of the drop's volume, (3 N s^3 / 4 pi)^(1/3).
//
// --medium puts the drop (colour +0.5) in a closed box of another liquid of the same density
// (colour -0.5, half-width max(2.5 R, R + 8 cm)) with interface tension sigma between them: the
// jump is the drop's interior pressure less the medium's (3 spacings clear of the drop and the
// walls), the period Lamb's for a drop in a liquid, 2 pi / sqrt(24 sigma / (5 rho R^3)).
//
//   drop_bench [--solvers dfsph,wcsph] [--radii 0.035,0.05,0.08] [--end 1] [--period-radius 0.05]
//              [--trace] [--medium] [--profile] [--perturb N] [--set key=value]...
//   --trace: the n = 2 drop's quadrupole moment every 0.02 s; --profile: each static drop's last frame, pressure
//   and density per shell half a spacing thick, drop and medium apart; --perturb N: each static drop
//   N more times, its viscosity raised in steps of 3.7e-4 of itself, and how many hold within 10 %.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <cmath>
#include <string>
#include <vector>

#include "bench_args.h"
#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

using namespace mf;

constexpr Real kSigma = 1.0, kRho = 1000.0, kSpacing = 0.01;

// --medium: the drop is one liquid ("drop", colour +0.5) inside another of the same density
// ("medium", -0.5) filling a closed box of half-width L, with interface tension sigma between them.
bool medium = false;
bool profile = false;  // --profile: each static drop's pressure and density by distance from its centre
Real mediumHalfWidth(Real R) { return std::max(2.5 * R, R + 0.08); }

// The scene's header and one water-like phase (its last line, `extra`, says which tension it feels).
std::string sceneHead(const std::string& solver, Real endTime, Real half) {
  return fmt::format(R"([scene]
name = "drop"
end_time = {}
domain_min = [{}, {}, {}]
domain_max = [{}, {}, {}]
[solver]
particle_spacing = {}
max_dt = 0.005
pressure = "{}"
)",
                     endTime, -half, -half, -half, half, half, half, kSpacing, solver);
}

std::string phase(const std::string& name, const std::string& extra) {
  return fmt::format("[[phase]]\nname = \"{}\"\nrest_density = {}\nstiffness = 100.0\nviscosity = 0.01\n{}\n", name, kRho, extra);
}

std::string dropScene(const std::string& solver, Real R, Real endTime) {
  const std::string sphere = fmt::format("shape = \"sphere\"\ncentre = [0.0, 0.0, 0.0]\nradius = {}\n", R);
  if (!medium) return freeDropScene(solver, R, kSpacing, kSigma, endTime);
  const Real L = mediumHalfWidth(R);
  return sceneHead(solver, endTime, L) + phase("medium", "interface_colour = -0.5") + phase("drop", "interface_colour = 0.5") +
         fmt::format(R"([[solid]]
name = "box"
shape = "box"
min = [{m}, {m}, {m}]
max = [{L}, {L}, {L}]
[[fluid]]
phase = "drop"
{e}[[fluid]]
phase = "medium"
min = [{m}, {m}, {m}]
max = [{L}, {L}, {L}]
[[fluid.subtract]]
{e}[effects.pressure]
[effects.viscosity]
[effects.interface_tension]
sigma = {sigma}
)",
                     fmt::arg("m", -L), fmt::arg("L", L), fmt::arg("e", sphere), fmt::arg("sigma", kSigma));
}

// The spacing and tension the scene ends up with, --set overrides included: the references
// (R from the particle count, 2 sigma / R, Rayleigh's period) follow them.
struct DropFluid {
  Real spacing, sigma;
};
DropFluid dropFluid(const Scene& scene) {
  Real sigma = kSigma;
  if (!medium) sigma = scene.phases.at(0).surfaceTension;
  else
    for (const EffectSpec& e : scene.effects)
      if (e.name == "interface_tension") sigma = e.number("sigma");
  return {scene.solver.particleSpacing, sigma};
}

bool inDrop(const ParticleSet& q, size_t i) { return !medium || q.phase[i] == 1; }

size_t dropCount(const ParticleSet& q) {
  size_t n = 0;
  for (size_t i = 0; i < q.size(); ++i) n += inDrop(q, i);
  return n;
}

Vec3 centroid(const ParticleSet& q) {
  return centroidOf(q, [&q](size_t i) { return inDrop(q, i); });
}

struct DropRatios {
  Real pressure = 0;  // interior pressure (in a medium: the jump) / (2 sigma / R)
  Real tension = 0;   // upper-half tension / (2 pi R sigma); DFSPH's free drop only, else 0
};

DropRatios staticDrop(const std::string& solver, Real R0, Real end, const std::vector<std::string>& sets) {
  Simulation sim(parseScene(dropScene(solver, R0, end), "drop.toml", sets));
  const auto [spacing, sigma] = dropFluid(sim.scene());
  const Real R = volumeRadius(dropCount(sim.particles()), spacing);
  const Real L = mediumHalfWidth(R0) - 3 * spacing;
  Real pressure = 0, cap = 0, outside = 0;
  int samples = 0;
  // --profile: shells half a spacing thick around the drop's centre, [medium, drop], summed over
  // the same steps as the pressure: pressure, density, particle count, and (drop) the inward pull
  // of the non-pressure forces.
  constexpr int kShells = 20;
  Real shellP[2][kShells] = {}, shellRho[2][kShells] = {}, shellN[2][kShells] = {}, shellPull[kShells] = {};
  sim.advanceTo(end, [&](const Simulation& s) {
    if (s.time() <= 0.5 * end) return;
    const ParticleSet& q = s.particles();
    const Vec3 c = centroid(q);
    if (profile)
      for (size_t i = 0; i < q.size(); ++i) {
        const Vec3 d = q.position[i] - c;
        const int b = int(length(d) / (0.5 * spacing)), k = inDrop(q, i);
        if (b >= kShells) continue;
        shellP[k][b] += q.mechanicalPressure(i), shellRho[k][b] += q.density[i] / q.restDensity[i], shellN[k][b] += 1;
        if (k == 1) shellPull[b] -= dot(q.force[i], normalize(d));
      }
    Real sum = 0, up = 0, out = 0;
    int count = 0, outCount = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      const Vec3 d = q.position[i] - c, x = q.position[i];
      if (!inDrop(q, i)) {  // the medium between the drop and the walls, clear of both
        if (length(d) > R + 3 * spacing && std::max({std::abs(x.x), std::abs(x.y), std::abs(x.z)}) < L)
          out += q.mechanicalPressure(i), ++outCount;
        continue;
      }
      if (length(d) < 0.5 * R) sum += q.mechanicalPressure(i), ++count;
      if (d.y > 0) up += q.force[i].y;  // the non-pressure forces of the step: tension (and viscosity)
    }
    if (count) pressure += sum / count, cap += up, ++samples;
    if (outCount) outside += out / outCount;
  });
  pressure /= samples, cap /= samples, outside /= samples;
  if (profile) {  // per shell: mean pressure and density per particle, particles and inward pull per step
    for (int b = 0; b < kShells; ++b) {
      const auto mean = [&](const Real (&sum)[2][kShells], int k) { return shellN[k][b] > 0 ? sum[k][b] / shellN[k][b] : 0.0; };
      fmt::print("  r {:.4f}: drop {:7.1f} p {:7.2f} rho {:.4f} pull {:8.5f} N | medium {:7.1f} p {:7.2f} rho {:.4f}\n",
                 (b + 0.5) * 0.5 * spacing, shellN[1][b] / samples, mean(shellP, 1), mean(shellRho, 1), shellPull[b] / samples,
                 shellN[0][b] / samples, mean(shellP, 0), mean(shellRho, 0));
    }
  }
  if (medium) {
    fmt::print("{:<6} static R = {:.4f} m in a medium ({:5} + {:5} particles, {:4} steps): interior p = {:6.2f} Pa, outside {:6.2f} Pa, "
               "jump {:6.2f} Pa, 2 sigma/R = {:6.2f} Pa, ratio {:.3f}\n",
               solver, R, dropCount(sim.particles()), sim.particles().size() - dropCount(sim.particles()), sim.counters().steps, pressure,
               outside, pressure - outside, 2 * sigma / R, (pressure - outside) / (2 * sigma / R));
    return {(pressure - outside) / (2 * sigma / R), 0};
  }
  const Real laplace = 2 * sigma / R, line = 2 * kPi * R * sigma;
  // WCSPH's pressure is one of the forces, so the upper half's force is the tension's only on DFSPH.
  const std::string tension = solver == "dfsph" ? fmt::format("; upper-half tension {:.4f} N, 2 pi R sigma = {:.4f} N, ratio {:.3f}",
                                                              -cap, line, -cap / line)
                                                : std::string();
  fmt::print("{:<6} static R = {:.4f} m ({:5} particles, {:4} steps): interior p = {:6.2f} Pa, 2 sigma/R = {:6.2f} Pa, ratio {:.3f}{}\n",
             solver, R, sim.particles().size(), sim.counters().steps, pressure, laplace, pressure / laplace, tension);
  return {pressure / laplace, solver == "dfsph" ? -cap / line : 0};
}

// --perturb N: the same drop again N times with its viscosity raised in steps of 3.7e-4 of itself,
// a change far below anything the viscosity does to a drop at rest: how many of the runs hold the
// figures within the issue's 10 % tells a robust result from a lucky one.
void perturbedDrops(const std::string& solver, Real R0, Real end, const std::vector<std::string>& sets, int runs) {
  const std::string phaseName = medium ? "drop" : "water";
  const Scene scene = parseScene(dropScene(solver, R0, end), "drop.toml", sets);
  const Real mu = scene.phases.at(size_t(scene.phaseIndex(phaseName))).viscosity;
  const bool hasTension = solver == "dfsph" && !medium;  // as staticDrop reports it
  int pressureWithin = 0, tensionWithin = 0;
  Real lowest = 1e300, highest = -1e300;
  for (int k = 1; k <= runs; ++k) {
    std::vector<std::string> perturbed = sets;
    perturbed.push_back(fmt::format("phase.{}.viscosity={:.10g}", phaseName, mu * (1 + 3.7e-4 * k)));
    const DropRatios r = staticDrop(solver, R0, end, perturbed);
    pressureWithin += std::fabs(r.pressure - 1) <= 0.1;
    tensionWithin += std::fabs(r.tension - 1) <= 0.1;
    const Real figure = hasTension ? r.tension : r.pressure;
    lowest = std::min(lowest, figure), highest = std::max(highest, figure);
  }
  fmt::print("{:<6} R0 = {:.3f} m, {} perturbed runs: pressure within 10 % in {}{}; {} ratio from {:.3f} to {:.3f}\n", solver, R0,
             runs, pressureWithin, hasTension ? fmt::format(", tension within 10 % in {}", tensionWithin) : std::string(),
             hasTension ? "tension" : "pressure", lowest, highest);
}

// The n = 2 period. A drop seeded on the lattice does not oscillate from a stretched start: the
// lattice holds it for a quarter second and then lets go all at once. So the sphere rests first
// (`relax` seconds), then gets the mode's potential flow with an amplitude of 20 % of R, and the
// period is read from the quadrupole moment Q = sum (x^2 - (y^2 + z^2) / 2) over three of
// Rayleigh's (or Lamb's) periods: the mean spacing of successive maxima, and of minima, each the
// extreme of Q within a quarter of that period either side.
void oscillatingDrop(const std::string& solver, Real R0, Real relax, const std::vector<std::string>& sets, bool trace) {
  const Real amplitude = 0.2;
  // Rayleigh's omega^2 = 8 sigma / (rho R^3); in a medium of density rho_o, Lamb's (1932, sec. 275)
  // 24 sigma / (R^3 (3 rho + 2 rho_o)), here with rho_o = rho.
  const Real stiffness = medium ? 24.0 / 5.0 : 8.0;
  const auto [spacing, sigma] = dropFluid(parseScene(dropScene(solver, R0, 1), "drop.toml", sets));
  const Real guess = 2 * kPi / std::sqrt(stiffness * sigma / (kRho * R0 * R0 * R0));
  const Real end = relax + 3 * guess;
  Simulation sim(parseScene(dropScene(solver, R0, end), "drop.toml", sets));
  const size_t seeded = dropCount(sim.particles());
  const Real R = volumeRadius(seeded, spacing);
  const Real omega = std::sqrt(stiffness * sigma / (kRho * R * R * R)), theory = 2 * kPi / omega;
  const auto inDrop = [&sim](size_t i) { return !medium || sim.particles().phase[i] == 1; };
  sim.advanceTo(relax);
  kickQuadrupoleMode(sim.mutableParticles(), inDrop, centroid(sim.particles()), R, omega, amplitude);
  sim.refresh();
  // The same flow from rest would stretch a sphere of N particles to Q = N R^2 (3 amplitude) / 5.
  const Real expected = kickedQuadrupole(seeded, R, amplitude);
  std::vector<Real> ts, qs;
  Real lastT = relax;
  sim.advanceTo(end, [&](const Simulation& s) {
    const Real t = s.time() - relax, m = quadrupoleMoment(s.particles(), inDrop);
    ts.push_back(t), qs.push_back(m);
    if (trace && std::floor(t / 0.02) != std::floor((lastT - relax) / 0.02)) fmt::print("  t {:.3f} s  Q {:+.4e} m^2\n", t, m);
    lastT = s.time();
  });
  const Oscillation o = oscillationOf(ts, qs, 0.25 * guess);
  const Real largest = o.largest;
  const size_t kept = dropCount(sim.particles());
  const std::string line = fmt::format("{:<6} n = 2  R = {:.4f} m{} ({:5} particles, {} flew off, {:4} steps, kicked after {:.1f} s): ", solver, R,
                                       medium ? " in a medium" : "", seeded, seeded - kept, sim.counters().steps, relax);
  const std::string name = medium ? "Lamb" : "Rayleigh";
  const KickOutcome outcome = kickOutcome(o, seeded, kept, expected);
  if (outcome == KickOutcome::CameApart) {
    fmt::print("{}broke up: |Q| up to {:.1f} times the kick's ({}'s period {:.3f} s)\n", line, largest / expected, name, theory);
    return;
  }
  if (outcome == KickOutcome::DiedOut) {
    fmt::print("{}no oscillation: |Q| at most {:.2e} m^2 against the kick's {:.2e} ({}'s period {:.3f} s)\n", line, largest, expected,
               name, theory);
    return;
  }
  fmt::print("{}period {:.3f} s ({} maxima, {} minima; largest |Q| {:.2f} of the kick's), {} {:.3f} s, ratio {:.3f}\n", line, o.period,
             o.maxima, o.minima, largest / expected, name, theory, o.period / theory);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> solvers = {"dfsph", "wcsph"}, sets;
  std::vector<Real> radii = {0.035, 0.05, 0.08};
  Real end = 1, periodRadius = 0.05, relax = 1.5;
  bool trace = false;
  int perturb = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--solvers" && more) solvers = bench::splitCommas(argv[++i]);
    else if (a == "--radii" && more) {
      radii.clear();
      for (const std::string& r : bench::splitCommas(argv[++i])) radii.push_back(bench::number(a, r));
    }
    else if (a == "--end" && more) end = bench::number(a, argv[++i]);
    else if (a == "--period-radius" && more) periodRadius = bench::number(a, argv[++i]);
    else if (a == "--set" && more) sets.push_back(argv[++i]);
    else if (a == "--relax" && more) relax = bench::number(a, argv[++i]);
    else if (a == "--perturb" && more) perturb = int(bench::whole(a, argv[++i]));
    else if (a == "--trace") trace = true;
    else if (a == "--medium") medium = true;
    else if (a == "--profile") profile = true;
    else {
      fmt::print(stderr, "usage: drop_bench [--solvers dfsph,wcsph] [--radii 0.035,0.05,0.08] [--end 1] [--period-radius 0.05] [--relax 1.5] [--trace] [--medium] [--profile] [--perturb N] [--set key=value]...\n");
      return 2;
    }
  }
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  try {
    for (const std::string& s : solvers) {
      for (const Real r : radii) {
        staticDrop(s, r, end, sets);
        if (perturb > 0) perturbedDrops(s, r, end, sets, perturb);
      }
      if (periodRadius > 0) oscillatingDrop(s, periodRadius, relax, sets, trace);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "drop_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
