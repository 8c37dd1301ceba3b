// `report accuracy`: each reference problem (report_problems.cpp) run over its ladder of settings
// with both pressure solvers; wall time and error against the reference per setting, each
// solver's Pareto front, and each solver's best setting for a few time budgets.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "report_problems.h"
#include "report_util.h"

namespace fs = std::filesystem;

namespace mf::report {

namespace {

// ---- output --------------------------------------------------------------------------------

// The Pareto front of one solver's rungs (the other solver's rows are never on it): each solver
// gets its own front, so that a reader sees what each one buys for its run time.
std::vector<bool> frontOf(const Problem& p, const std::vector<Measured>& r, bool alt, const std::string& solver) {
  std::vector<double> walls, errors;
  for (size_t k = 0; k < r.size(); ++k)
    walls.push_back(r[k].wall), errors.push_back(p.ladder[k].solver == solver ? p.errorOf(r[k], alt) : kNaN);
  return paretoFront(walls, errors);
}

// Both solvers' fronts in one flag per row.
std::vector<bool> frontsOf(const Problem& p, const std::vector<Measured>& r, bool alt) {
  std::vector<bool> any(r.size(), false);
  for (const auto& solver : solverNames()) {
    const std::vector<bool> f = frontOf(p, r, alt, solver);
    for (size_t k = 0; k < r.size(); ++k) any[k] = any[k] || f[k];
  }
  return any;
}

// Columns `pareto` (on its own solver's front) and `status` come last (the CI check reads them
// there).
Table resultTable(const Problem& p, const std::vector<Measured>& results) {
  const std::vector<bool> front = frontsOf(p, results, false), altFront = frontsOf(p, results, true);
  Table t;
  t.header = {"problem", "solver", "setting", "spacing_m", "dt_factor", "variant", "particles", "steps", "wall_s", "cpu_s", "load_1min", "error"};
  for (const auto& e : p.extraColumns) t.header.push_back(e);
  if (p.altExtra >= 0) t.header.push_back("pareto_" + p.extraColumns[size_t(p.altExtra)]);
  t.header.push_back("pareto");
  t.header.push_back("status");
  for (size_t k = 0; k < results.size(); ++k) {
    const Setting& s = p.ladder[k];
    const Measured& m = results[k];
    std::vector<std::string> row = {p.name, s.solver, s.label, fmtNumber(s.spacing, 6), fmtNumber(s.dtFactor), s.variant,
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

// Gnuplot data block of (wall, error, label) of one solver's settings with an error, by wall
// time; `onlyFront` keeps its Pareto points (joined by a line in the plot). A log axis has no
// zero, so an error of exactly 0 (the layered problem: no particle on the wrong side) is drawn at
// `zeroAt`, below every other point, and labelled "error = 0".
std::string dataBlock(const std::string& name, const Problem& p, const std::vector<Measured>& r, bool alt,
                      bool onlyFront, const std::string& solver, double zeroAt) {
  const std::vector<bool> front = frontOf(p, r, alt, solver);
  std::vector<size_t> order;
  for (size_t k = 0; k < r.size(); ++k)
    if (p.ladder[k].solver == solver && std::isfinite(p.errorOf(r[k], alt)) && p.errorOf(r[k], alt) >= 0 &&
        (!onlyFront || front[k]))
      order.push_back(k);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return r[a].wall < r[b].wall; });
  std::string out = "$" + name + " << EOD\n";
  for (size_t k : order) {
    const double e = p.errorOf(r[k], alt);
    out += fmt::format("{:.6g} {:.6g} \"{}{}\"\n", r[k].wall, e > 0 ? e : zeroAt, escapeGnuplot(p.ladder[k].label),
                       e > 0 ? "" : ": error = 0");
  }
  return out + "EOD\n";
}

// Where a zero error is drawn: a third of the smallest positive error of the plot.
double zeroLevel(const Problem& p, const std::vector<Measured>& r) {
  double least = std::numeric_limits<double>::infinity();
  for (bool alt : {false, true}) {
    if (alt && p.altExtra < 0) continue;
    for (const Measured& m : r)
      if (std::isfinite(p.errorOf(m, alt)) && p.errorOf(m, alt) > 0) least = std::min(least, p.errorOf(m, alt));
  }
  return std::isfinite(least) ? least / 3 : 1e-6;
}

// How a solver's series look: WCSPH red circles, DFSPH blue triangles; a second error (the dam
// break's shifted RMS) in a lighter tone of the same hue with squares / diamonds and a dashed front.
struct Style {
  const char* colour;
  int point, openPoint;
};
Style styleOf(const std::string& solver, bool alt) {
  if (solver == "wcsph") return alt ? Style{"#ff7f0e", 5, 4} : Style{"#d62728", 7, 6};
  return alt ? Style{"#17becf", 13, 12} : Style{"#1f77b4", 9, 8};
}

// Error (log) against wall time (log): per solver every setting labelled and its Pareto front
// joined; a problem with a second error gets those points and fronts too.
std::string paretoScript(const Problem& p, const std::vector<Measured>& r, const Machine& machine) {
  std::string data, plots;
  const double zeroAt = zeroLevel(p, r);
  for (bool alt : {false, true}) {
    if (alt && p.altExtra < 0) continue;
    const std::string what = alt ? p.altName : p.errorName;
    for (const auto& solver : solverNames()) {
      if (std::none_of(p.ladder.begin(), p.ladder.end(), [&](const Setting& s) { return s.solver == solver; })) continue;
      const std::string all = solver + (alt ? "alt" : ""), front = all + "front";
      data += dataBlock(all, p, r, alt, false, solver, zeroAt) + dataBlock(front, p, r, alt, true, solver, zeroAt);
      const Style st = styleOf(solver, alt);
      plots += fmt::format(
          "{sep}${all} using 1:2 with points pt {pt} ps 1.3 lc rgb \"{c}\" title \"{solver}: {what}\", \\\n"
          "     ${front} using 1:2 with linespoints lw 2 dt {dt} pt {open} ps 2.2 lc rgb \"{c}\" title \"{solver}: its Pareto front\", \\\n"
          "     ${all} using 1:2:3 with labels {side} offset {off} rotate by 40 font \"sans,8\" tc rgb \"{c}\" notitle",
          fmt::arg("sep", plots.empty() ? "" : ", \\\n     "), fmt::arg("all", all), fmt::arg("front", front),
          fmt::arg("pt", st.point), fmt::arg("open", st.openPoint), fmt::arg("c", st.colour),
          fmt::arg("solver", solver), fmt::arg("what", escapeGnuplot(what)), fmt::arg("dt", alt ? 2 : 1),
          fmt::arg("side", alt ? "right" : "left"), fmt::arg("off", alt ? "-0.6,-0.5" : "0.6,0.5"));
    }
  }
  return fmt::format(R"gp(set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_{name}.png.tmp"
{data}set logscale xy
set grid
set title "{title}: WCSPH and DFSPH"
set xlabel "wall time (s), {machine}"
set ylabel "{error} (log)"
set key outside right top
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
    // DFSPH dashed, so that the two solvers' curves part at a glance.
    plots += fmt::format("$s{} using 1:2 with lines lw 1.5 dt {} title \"{} {}\", \\\n     ", k,
                         p.ladder[k].solver == "dfsph" ? 2 : 1, p.ladder[k].solver, escapeGnuplot(p.ladder[k].label));
  }
  std::string exp = "$exp << EOD\n";
  for (const auto& [T, Z] : surgeFrontData()) exp += fmt::format("{} {}\n", T, Z);
  exp += "EOD\n";
  return fmt::format(R"gp(set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "dam_break_front.png.tmp"
{data}{exp}set grid
set title "Dam break surge front, WCSPH (solid) and DFSPH (dashed), against Martin & Moyce (1952), Table 2 (no time shift)"
set xlabel "T = t sqrt(2g/a)"
set ylabel "Z = x/a"
set xrange [0:3.4]
set key top left
plot {plots}$exp using 1:2 with points pt 7 ps 1.5 lc rgb "black" title "Martin & Moyce 1952, Table 2"
)gp",
                     fmt::arg("data", data), fmt::arg("exp", exp), fmt::arg("plots", plots));
}

// For each budget, per solver the lowest-error setting that ran within it.
std::string budgetTable(const Problem& p, const std::vector<Measured>& r, bool alt) {
  std::string out = "| time budget |", rule = "|---|";
  for (const auto& solver : solverNames())
    out += fmt::format(" best {0} setting | {0} error | wall time |", solver), rule += "---|---|---|";
  out += "\n" + rule + "\n";
  double maxWall = 0;
  for (const auto& m : r) maxWall = std::max(maxWall, m.wall);
  for (double budget : {0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0}) {
    std::string line = fmt::format("| {} s |", budget);
    bool any = false;
    for (const auto& solver : solverNames()) {
      int best = -1;
      for (size_t k = 0; k < r.size(); ++k) {
        const double e = p.errorOf(r[k], alt);
        if (p.ladder[k].solver == solver && r[k].wall <= budget && std::isfinite(e) &&
            (best < 0 || e < p.errorOf(r[size_t(best)], alt)))
          best = int(k);
      }
      if (best < 0) {
        line += " - | - | - |";
        continue;
      }
      any = true;
      line += fmt::format(" {} | {} | {:.2f} s |", p.ladder[size_t(best)].label, fmtNumber(p.errorOf(r[size_t(best)], alt), 3),
                          r[size_t(best)].wall);
    }
    if (any) out += line + "\n";
    if (budget >= maxWall) break;  // every setting fits: larger budgets say nothing new
  }
  return out;
}

std::string frontCsv(const Problem& p, const std::vector<Measured>& r) {
  std::string out = "solver,setting,T,Z\n";
  for (size_t k = 0; k < r.size(); ++k)
    for (const auto& [T, Z] : r[k].curve)
      out += fmt::format("{},{},{:.5g},{:.5g}\n", p.ladder[k].solver, p.ladder[k].label, T, Z);
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
  if (!p.note.empty()) out += p.note + "\n";
  if (!p.dfsphNote.empty()) out += "**DFSPH rungs**: " + p.dfsphNote + "\n\n";
  out += fmt::format("![error against wall time](accuracy_{}.png)\n\n", p.name);
  std::vector<std::string> cols = {"solver", "setting", "particles", "steps", "wall_s", "cpu_s", "load_1min", "error"};
  for (const auto& e : p.extraColumns) cols.push_back(e);
  for (size_t c = 0; c < t.header.size(); ++c)
    if (t.header[c].rfind("pareto", 0) == 0) {
      cols.push_back(t.header[c]);
      for (auto& row : t.rows) row[c] = row[c] == "1" ? "**yes**" : "";  // on its own solver's front
    }
  const bool anyFailed = std::any_of(r.begin(), r.end(), [](const Measured& m) { return m.status != "ok"; });
  if (anyFailed) cols.push_back("status");
  out += t.markdown(cols) + "\n";
  out += "Best setting for a time budget, per solver (the lowest error among that solver's settings that ran "
         "within it, on this machine):\n\n" + budgetTable(p, r, false) + "\n";
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
         "Every rung runs with both pressure solvers (`solver.pressure` = `wcsph` and `dfsph`, "
         "docs/pressure_solvers.md) on the same reference, except where a section says a WCSPH variant has no "
         "meaning for DFSPH. The time-step factor f scales the time-step criteria: `solver.cfl` = 0.4 f, "
         "`solver.force_factor` = 0.25 f and the scene's `solver.max_dt` times f (heat diffusion: its "
         "`stability_factor` = 0.5 f, at most 1). The cap binds DFSPH on most steps and WCSPH on none. `solver.cfl` "
         "limits a different thing per solver: WCSPH's step follows the sound speed, dt <= cfl h / (sqrt(k) + v_max); "
         "DFSPH's follows the flow, dt <= cfl spacing / v_max, and has no stiffness (its pressure is solved to "
         "`solver.density_tolerance`, 5e-4 by default, kept here). Every setting is a scene-file value; nothing is "
         "fitted to the reference data. A setting the watchdog stopped has no error and is left out of the Pareto "
         "fronts. Each solver has its own front: the settings of that solver that no other setting of it beats in "
         "both wall time and error (column `pareto`; in the plots WCSPH red circles, DFSPH blue triangles).\n\n";
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
      fmt::print(stderr, "[accuracy {}/{}] {} {} {}: {} particles, {} steps, {:.2f} s, error {}{}  (elapsed {})\n", ++done,
                 total, p.name, s.solver, s.label, m.particles, m.steps, m.wall, fmtNumber(m.error, 4),
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
