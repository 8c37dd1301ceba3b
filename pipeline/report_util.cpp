#include "report_util.h"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "pipeline/process.h"
#include "sim/file_util.h"

namespace fs = std::filesystem;

namespace mf::report {

bool Options::selected(const std::string& name) const {
  return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
}

std::string Machine::describe() const {
  return fmt::format("{}, {} hardware threads, {} used by TBB", cpuModel, hardwareThreads, tbbThreads);
}

Machine currentMachine() {
  Machine m;
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      m.cpuModel = colon == std::string::npos ? line : line.substr(colon + 2);
      break;
    }
  if (m.cpuModel.empty()) m.cpuModel = "unknown CPU (no model name in /proc/cpuinfo)";
  m.hardwareThreads = std::thread::hardware_concurrency();
  m.tbbThreads = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  return m;
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  if (!(in >> a >> b >> c)) return "unknown";
  return a + " " + b + " " + c;
}

double loadAverage1() {
  std::ifstream in("/proc/loadavg");
  double a = -1;
  in >> a;
  return a;
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return buf;
}

void Table::add(std::vector<std::string> row) {
  if (row.size() != header.size()) throw std::logic_error("report table: row width differs from header");
  rows.push_back(std::move(row));
}

size_t Table::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw std::logic_error("report table: no column " + name);
  return size_t(it - header.begin());
}

namespace {
std::string csvCell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}
std::string markdownCell(const std::string& s) {
  std::string r;
  for (char c : s) r += c == '|' ? std::string("\\|") : std::string(1, c == '\n' ? ' ' : c);
  return r;
}
}  // namespace

std::string Table::csv() const {
  std::string out;
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + csvCell(cells[k]);
    out += "\n";
  };
  line(header);
  for (const auto& r : rows) line(r);
  return out;
}

std::string Table::markdown(const std::vector<std::string>& columns, const std::vector<std::string>& titles) const {
  std::vector<size_t> idx;
  for (const auto& c : columns.empty() ? header : columns) idx.push_back(column(c));
  std::string out = "|", rule = "|";
  for (size_t k = 0; k < idx.size(); ++k) {
    out += " " + markdownCell(k < titles.size() ? titles[k] : header[idx[k]]) + " |";
    rule += "---|";
  }
  out += "\n" + rule + "\n";
  for (const auto& r : rows) {
    out += "|";
    for (size_t k : idx) out += " " + markdownCell(r[k]) + " |";
    out += "\n";
  }
  return out;
}

void writeText(const std::string& path, const std::string& text) { writeFileAtomically(path, text); }

bool gnuplotAvailable() { return !pipeline::findOnPath("gnuplot").empty(); }

bool plot(const Options& opt, const std::string& name, const std::string& script, const std::string& png) {
  const fs::path dir(opt.out);
  const std::string gp = (dir / (name + ".gp")).string();
  writeText(gp, script);  // kept beside the data: anyone can re-plot or restyle
  if (!opt.plots) return true;
  if (!gnuplotAvailable()) {
    fmt::print(stderr, "report: gnuplot not found (Debian package gnuplot-nox): {} not drawn; its data and {} are written\n", png, gp);
    return false;
  }
  const std::string tmp = png + ".tmp";
  // An argument vector, no shell: the folder and names reach gnuplot as they are.
  const fs::path log = dir / (name + ".gnuplot.log");
  int status = -1;
  try {
    status = pipeline::runProgram({"gnuplot", name + ".gp"}, {dir.string(), "", log.string()});
  } catch (const std::exception& e) {
    fmt::print(stderr, "report: {}\n", e.what());
  }
  if (status != 0 || !fs::exists(tmp) || fs::file_size(tmp) == 0) {
    fmt::print(stderr, "report: gnuplot failed on {} (see {}.gnuplot.log)\n", gp, (dir / name).string());
    return false;
  }
  fs::remove(dir / (name + ".gnuplot.log"));
  fs::rename(tmp, png);
  return true;
}

std::vector<bool> paretoFront(const std::vector<double>& cost, const std::vector<double>& error) {
  std::vector<bool> front(cost.size(), false);
  for (size_t i = 0; i < cost.size(); ++i) {
    if (!std::isfinite(error[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < cost.size() && !dominated; ++j)
      dominated = j != i && std::isfinite(error[j]) && cost[j] <= cost[i] && error[j] <= error[i] &&
                  (cost[j] < cost[i] || error[j] < error[i]);
    front[i] = !dominated;
  }
  return front;
}

std::string fmtNumber(double v, int digits) {
  if (std::isnan(v)) return "-";
  return fmt::format("{:.{}g}", v, digits);
}

std::string formatDuration(double s) {
  return s < 60 ? fmt::format("{:.1f}s", s) : fmt::format("{}m{:02d}s", int(s / 60), int(s) % 60);
}

std::string escapeGnuplot(const std::string& s) {
  std::string r;
  for (char c : s) {
    if (c == '"' || c == '\\') r += '\\';
    r += c;
  }
  return r;
}

}  // namespace mf::report
