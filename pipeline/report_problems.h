// The reference problems of `report accuracy` (report_problems.cpp): each problem's scene, its
// error against the reference, and its ladder of settings for both pressure solvers. The tables,
// plots and page are report_accuracy.cpp's.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace mf::report {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The two pressure solvers, in the order tables and plots show them.
const std::vector<std::string>& solverNames();  // {"wcsph", "dfsph"}

/// One rung of a ladder. `dtFactor` multiplies every time-step criterion the problem is limited
/// by (cfl 0.4 and force_factor 0.25 by default; the diffusion stability factor 0.5 for heat).
struct Setting {
  double spacing = 0;
  double dtFactor = 1;
  std::string variant;   // the formulation choice where the problem has one
  std::string label;     // short name for tables and plots (without the solver)
  std::string solver = "wcsph";  // solver.pressure
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
  std::string dfsphNote;   // which WCSPH rungs have no DFSPH twin, and why ("" if all do)
  std::string note;        // a paragraph of the page after the error's definition ("" if none)
  double errorOf(const Measured& m, bool alt) const {
    return !alt ? m.error : size_t(altExtra) < m.extras.size() ? m.extras[size_t(altExtra)] : kNaN;
  }
};

std::vector<Problem> problems(bool quick);

/// Martin & Moyce 1952, Table 2: (T, Z) of the surge front, for the front plot.
const std::vector<std::pair<double, double>>& surgeFrontData();
constexpr double kDamBreakTMax = 3.0;    // compare the points with T <= 3 (the range)
constexpr double kDamBreakShiftT = 0.175;  // gate-release shift in T used by Lethe's Martin-Moyce example

}  // namespace mf::report
