// `report accuracy`'s static drop: a free water drop in zero gravity against Laplace's pressure
// jump 2 sigma / R, and, in the same run, its n = 2 oscillation against Rayleigh's period
// (the measures of bench/drop_bench, through the shared yardsticks of sim/diagnostics.h).
#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "report_run.h"
#include "sim/diagnostics.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace mf::report {

namespace {

constexpr double kRadius = 0.05, kSigma = 1.0, kRho = 1000.0;
constexpr double kStaticFrom = 0.5, kStaticTo = 1.0;  // the interior pressure is averaged over these steps
constexpr double kRelax = 1.5;                        // then the drop rests until here and is kicked
constexpr double kAmplitude = 0.2;                    // the kick's surface displacement over R

// Rayleigh's angular frequency of the n = 2 mode, omega^2 = 8 sigma / (rho R^3).
double rayleighOmega(double R) { return std::sqrt(8 * kSigma / (kRho * R * R * R)); }

Measured runStaticDrop(const Setting& s) {
  const double guess = 2 * kPi / rayleighOmega(kRadius), end = kRelax + 3 * guess;
  const Scene scene =
      withFactor(parseScene(freeDropScene(s.solver, kRadius, s.spacing, kSigma, end), "<report:static_drop>", rungOverrides(s)), s);
  double pressure = 0, R = 0;
  int samples = 0;
  size_t seeded = 0, kept = 0;
  std::vector<double> ts, qs;
  const auto all = [](size_t) { return true; };
  Measured m = runCase(scene, [&](Simulation& sim, Stopwatch& sw) {
    seeded = sim.particles().size();
    R = volumeRadius(seeded, s.spacing);
    sim.advanceTo(kRelax, [&](const Simulation& x) {
      if (x.time() <= kStaticFrom || x.time() > kStaticTo) return;
      sw.exclude([&] {
        const double p = meanPressureNearCentroid(x.particles(), 0.5 * R);
        if (!std::isnan(p)) pressure += p, ++samples;
      });
    });
    sw.exclude([&] { kickQuadrupoleMode(sim.mutableParticles(), all, centroidOf(sim.particles()), R, rayleighOmega(R), kAmplitude); });
    sim.refresh();
    sim.advanceTo(end, [&](const Simulation& x) {
      sw.exclude([&] { ts.push_back(x.time()), qs.push_back(quadrupoleMoment(x.particles(), all)); });
    });
    kept = sim.particles().size();
  });
  if (m.status != "ok" || samples == 0) return m;
  const double laplace = 2 * kSigma / R, ratio = pressure / samples / laplace;
  m.error = std::fabs(ratio - 1);
  // The period, unless the drop came apart or the kick died out.
  const double expected = kickedQuadrupole(seeded, R, kAmplitude);
  const Oscillation o = oscillationOf(ts, qs, 0.25 * guess);
  const double period = kickOutcome(o, seeded, kept, expected) == KickOutcome::Period ? o.period : kNaN;
  const double periodRatio = period / (2 * kPi / rayleighOmega(R));
  m.extras = {std::fabs(periodRatio - 1), ratio, periodRatio, o.largest / expected};
  return m;
}

}  // namespace

Problem staticDropProblem(bool quick) {
  Problem p{"static_drop", "A free drop against Laplace and Rayleigh", "|interior pressure / (2 sigma / R) - 1|",
            "the mean pressure within R/2 of the drop's centroid (DFSPH: both solves' pressures), averaged over the steps "
            "of 0.5 .. 1 s, against 2 sigma / R, R the radius of the particles' volume; second error: |period / "
            "Rayleigh's - 1|, the period of the n = 2 mode (kicked at 1.5 s with its own potential flow, 20 % of R) "
            "read from the maxima and minima of sum (x^2 - (y^2 + z^2) / 2) over three of Rayleigh's periods, "
            "2 pi / sqrt(8 sigma / (rho R^3)); none (empty) where the drop came apart or the kick died out",
            "A water drop of radius 5 cm (rho0 = 1000, mu = 0.01 Pa s, k = 100 for WCSPH, surface tension sigma = 1 N/m, "
            "`effects.surface_tension` with its defaults: the fitted curvature on DFSPH, -div(n/|n|) on WCSPH), zero gravity, seeded on the lattice at the spacing; the scene "
            "of bench/drop_bench (sim/diagnostics.h, freeDropScene).",
            {"period_error", "pressure_ratio", "period_ratio", "largest_Q_over_kick"}, {}, runStaticDrop, 0,
            "|period / Rayleigh's - 1|", "", ""};
  auto add = [&](double spacing, double f) {
    for (const auto& solver : solverNames()) p.ladder.push_back(rung(spacing, f, "", mm(spacing), solver));
  };
  if (quick) {
    add(kRadius / 4, 1);
  } else {
    for (double n : {4.0, 5.0, 20.0 / 3, 10.0}) add(kRadius / n, 1);
    for (double n : {5.0, 10.0}) add(kRadius / n, 2);
  }
  return p;
}

}  // namespace mf::report
