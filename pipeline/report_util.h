// Shared pieces of the report command: options, the machine description, tables written as CSV
// and Markdown, gnuplot plots, the Pareto front, and the two reports' entry points.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "sim/diagnostics.h"

namespace mf::report {

struct Options {
  std::string out = "report";
  bool quick = false;
  bool plots = true;
  int threads = 0;                  // 0: all hardware threads
  std::vector<std::string> only;    // problem / sweep names; empty: all
  std::string commandLine;          // as typed, for the page
  bool selected(const std::string& name) const;
};

/// CPU model, cores and the threads TBB may use: run times mean nothing without them.
struct Machine {
  std::string cpuModel;
  unsigned hardwareThreads = 0;
  int tbbThreads = 0;
  std::string describe() const;
};
Machine currentMachine();
/// The 1, 5 and 15 minute load averages (/proc/loadavg): other work on the machine slows the runs.
std::string loadAverage();

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
/// CPU seconds of this process, all threads: beside the wall time, it shows what other work on a
/// shared machine took away (wall time grows with the load, CPU time hardly).
double processCpuSeconds();
/// The 1-minute load average alone, per run.
double loadAverage1();
std::string utcNow();

/// A table of preformatted cells, written as CSV (every column) and as Markdown.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  void add(std::vector<std::string> row);
  std::string csv() const;
  /// Markdown of the named columns (all when empty), optionally under other titles.
  std::string markdown(const std::vector<std::string>& columns = {}, const std::vector<std::string>& titles = {}) const;
  size_t column(const std::string& name) const;
};

/// Writes under a temporary name, then renames (a killed report leaves no half file).
void writeText(const std::string& path, const std::string& text);

/// Runs gnuplot on `script` (saved as DIR/NAME.gp) which must write to `png`.tmp; renames the
/// result to `png`. Returns false, after saying why, when gnuplot is missing or fails.
bool plot(const Options& opt, const std::string& name, const std::string& script, const std::string& png);
bool gnuplotAvailable();

/// Flags the points not dominated in (cost, error): no other point is at most as costly
/// and at most as wrong, and strictly better in one of the two.
std::vector<bool> paretoFront(const std::vector<double>& cost, const std::vector<double>& error);

std::string fmtNumber(double v, int digits = 3);  // %.{digits}g; "-" for NaN
std::string formatDuration(double seconds);  // "12.3s" or "4m05s"
// tomlReal (a TOML float literal for scene overrides) is mf::tomlReal, sim/diagnostics.h.
std::string escapeGnuplot(const std::string& s);

int runAccuracy(const Options& opt, const Machine& machine);
int runStability(const Options& opt, const Machine& machine);

}  // namespace mf::report
