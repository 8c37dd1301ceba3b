// What the reference problems of `report accuracy` share (report_problems.cpp, report_drop.cpp):
// a rung's scene overrides, the timing of a run without the report's own measurements, and the
// run of one rung that turns a watchdog stop into a result.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "report_problems.h"
#include "report_util.h"
#include "sim/scene.h"

namespace mf {
class Simulation;
}

namespace mf::report {

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

/// The rung's solver and time-step factor as scene overrides.
std::vector<std::string> rungOverrides(const Setting& s);

/// The scene with its max_dt cap scaled by the rung's factor.
Scene withFactor(Scene scene, const Setting& s);

/// Runs `advance` on a fresh simulation of `scene`; a watchdog stop is a result (status "stopped:
/// ..."), not a failure of the report.
Measured runCase(const Scene& scene, const std::function<void(Simulation&, Stopwatch&)>& advance);

/// A rung of the ladder, labelled "<spacingName> f=<f>[ <variant>]".
Setting rung(double spacing, double f, std::string variant, const std::string& spacingName, const std::string& solver);

/// A spacing as "<mm>mm", 3 significant digits.
std::string mm(double spacing);

/// The static drop against Laplace and its n = 2 period against Rayleigh (report_drop.cpp).
Problem staticDropProblem(bool quick);

}  // namespace mf::report
