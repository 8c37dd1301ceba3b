#include "report.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

#include "report_util.h"

namespace mf::report {

namespace {

const std::vector<std::string> kNames = {"dam_break", "hydrostatic", "heat_diffusion", "layered", "static_drop",  // accuracy
                                         "stiffness", "density_tolerance", "density_ratio", "viscosity", "dt_factor",
                                         "temperature", "spacing", "surface_tension"};  // stability

void usage(std::FILE* to) {
  fmt::print(to,
             "usage: multifluid report accuracy|stability|all [--out DIR] [--quick] [--threads N] [--only NAME,...] [--no-plots]\n"
             "\n"
             "accuracy:  error against run time on reference problems (dam_break against Martin & Moyce 1952,\n"
             "           hydrostatic, heat_diffusion against erf, layered two fluids, static_drop against Laplace and\n"
             "           Rayleigh), a ladder of settings each, run\n"
             "           with both pressure solvers (wcsph, dfsph); writes DIR/accuracy.md, DIR/accuracy_<problem>.csv\n"
             "           and .png (error against wall time, each solver's Pareto front marked).\n"
             "stability: sweeps of stiffness (DFSPH: density_tolerance), density ratio, viscosity, time-step factor,\n"
             "           temperature range, particle spacing and surface tension, each on both solvers; writes DIR/stability.md,\n"
             "           DIR/stability.csv, DIR/stability.png (compression) and DIR/stability_energy.png (energy growth).\n"
             "--quick    a small ladder (what CI runs: about 1.5 min on a loaded 2-core machine); the default is the full one\n"
             "           (WCSPH alone took about 30 minutes on 2 busy cores; DFSPH's rungs come on top).\n"
             "--only     problems (dam_break, hydrostatic, heat_diffusion, layered, static_drop) or sweeps (stiffness,\n"
             "           density_tolerance, density_ratio, viscosity, dt_factor, temperature, spacing, surface_tension) to run;\n"
             "           stiffness also runs its DFSPH counterpart density_tolerance.\n"
             "--no-plots write the gnuplot scripts but do not run gnuplot.\n"
             "DIR defaults to report/. Run times are measured on this machine, which the pages name.\n");
}

std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream ss(s);
  for (std::string p; std::getline(ss, p, ',');)
    if (!p.empty()) parts.push_back(p);
  return parts;
}

// Parses the options after the report name; returns -1 when fine, else the exit status.
int parseOptions(const std::vector<std::string>& args, Options& opt) {
  for (size_t k = 1; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string* { return k + 1 < args.size() ? &args[++k] : nullptr; };
    const std::string* v = nullptr;
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--quick") {
      opt.quick = true;
    } else if (a == "--no-plots") {
      opt.plots = false;
    } else if (a == "--out" || a == "--threads" || a == "--only") {
      if (!(v = value())) {
        fmt::print(stderr, "multifluid report: {} needs a value\n", a);
        return 2;
      }
      if (a == "--out") opt.out = *v;
      if (a == "--only") opt.only = splitComma(*v);
      if (a == "--threads" && (v->empty() || v->find_first_not_of("0123456789") != std::string::npos || v->size() > 4 ||
                               (opt.threads = std::stoi(*v)) < 1)) {
        fmt::print(stderr, "multifluid report: --threads must be at least 1\n");
        return 2;
      }
    } else {
      fmt::print(stderr, "multifluid report: unknown option {}\n", a);
      usage(stderr);
      return 2;
    }
  }
  for (const auto& name : opt.only)
    if (std::find(kNames.begin(), kNames.end(), name) == kNames.end()) {
      fmt::print(stderr, "multifluid report: --only: unknown name '{}'\n", name);
      return 2;
    }
  return -1;
}

}  // namespace

int runReportCommand(const std::vector<std::string>& args) {
  const bool help = !args.empty() && (args[0] == "-h" || args[0] == "--help");
  if (args.empty() || help || (args[0] != "accuracy" && args[0] != "stability" && args[0] != "all")) {
    usage(help ? stdout : stderr);
    return help ? 0 : 2;
  }
  Options opt;
  opt.commandLine = "multifluid report";
  for (const auto& a : args) opt.commandLine += " " + a;
  if (const int status = parseOptions(args, opt); status >= 0) return status;

  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  const Machine machine = currentMachine();
  std::filesystem::create_directories(opt.out);
  fmt::print(stderr, "report {}{} on {} -> {}\n", args[0], opt.quick ? " (quick)" : "", machine.describe(), opt.out);
  if (opt.plots && !gnuplotAvailable())
    fmt::print(stderr, "report: gnuplot not found; CSV and Markdown are written, plots are not (install gnuplot-nox, or pass --no-plots)\n");

  int status = 0;
  if (args[0] == "accuracy" || args[0] == "all") status = std::max(status, runAccuracy(opt, machine));
  if (args[0] == "stability" || args[0] == "all") status = std::max(status, runStability(opt, machine));
  return status;
}

}  // namespace mf::report
