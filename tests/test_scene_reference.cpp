// docs/scene_reference.md cannot go stale: every key the parser asks for, while reading every
// shipped scene and snippets that take its other branches (shapes, subtractions, camera keys,
// ramps), and every effect's declared keys, must appear in the reference's row for its table,
// and every literal default the reference gives must be the one the parser takes.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "sim/effect.h"
#include "pipeline/scene_stages.h"

namespace {

using mf::Real;

// Branches the shipped scenes do not take, each a scene of its own (parsed with overrides).
const char* kBase = R"([scene]
name = "ref"
domain_min = [-0.2, -0.2, -0.2]
domain_max = [0.3, 0.3, 0.3]
[solver]
particle_spacing = 0.01
pressure = "dfsph"
[[phase]]
name = "water"
rest_density = 1000.0
[[solid]]
name = "vase"
shape = "revolution"
base = [0.0, 0.0, 0.0]
profile = [[0.0, 0.05], [0.1, 0.06]]
[[solid]]
name = "tank"
shape = "box"
min = [0.1, 0.0, 0.1]
max = [0.2, 0.1, 0.2]
open_top = true
[[fluid]]
phase = "water"
shape = "sphere"
centre = [0.0, 0.05, 0.0]
radius = 0.03
velocity = [0.1, 0.0, 0.0]
[[fluid.subtract]]
shape = "box"
min = [-0.01, 0.04, -0.01]
max = [0.01, 0.06, 0.01]
[[fluid]]
phase = "water"
shape = "ellipsoid"
centre = [0.15, 0.05, 0.15]
radii = [0.02, 0.01, 0.02]
[[fluid]]
phase = "water"
shape = "cylinder"
base = [0.15, 0.0, 0.15]
radius = 0.02
height = 0.02
[[fluid.subtract]]
shape = "sphere"
centre = [0.15, 0.01, 0.15]
radius = 0.005
[effects.gravity]
[effects.damping]
[surfacing]
attributes = ["dye"]
[render]
[[render.camera_key]]
time = 0.0
position = [0.0, 0.2, 0.5]
look_at = [0.0, 0.05, 0.0]
[render.material.water]
absorption_ramp = { attribute = "dye", range = [0.0, 1.0], colours = [[1.0, 1.0, 1.0], [1.0, 2.0, 3.0]] }
[render.material.vase]
thickness = 0.004
)";

/// A parser path as the reference names its table: indices dropped, a material's name (and its
/// ramp's sub-table) as NAME, an effect's list entries under the effect.
std::pair<std::string, std::string> tableAndKey(const std::string& path) {
  std::string p = std::regex_replace(path, std::regex(R"(\[\d+\])"), "");
  const size_t dot = p.rfind('.');
  if (dot == std::string::npos) return {"", p};
  std::string table = p.substr(0, dot), key = p.substr(dot + 1);
  table = std::regex_replace(table, std::regex(R"(^render\.material\.[^.]+(\.[a-z_]+_ramp)?$)"), "render.material.NAME");
  table = std::regex_replace(table, std::regex(R"(^(effects\.[a-z_]+)\..*$)"), "$1");
  return {table, key};
}

/// The reference's rows, by table: "[scene]" -> "scene", "[[fluid.subtract]]" ->
/// "fluid.subtract", an effect's row "gravity" -> "effects.gravity"; a row with an empty first
/// cell continues the table above it.
std::map<std::string, std::string> referenceRows(const std::string& text) {
  std::map<std::string, std::string> rows;
  std::istringstream in(text);
  std::string line, table;
  bool effects = false;
  while (std::getline(in, line)) {
    if (line.rfind("| effect |", 0) == 0) effects = true;
    if (line.rfind("|", 0) != 0 || line.rfind("|---", 0) == 0) continue;
    const size_t end = line.find('|', 1);
    std::string first = line.substr(1, end - 1);
    first = std::regex_replace(first, std::regex(R"([\s`\[\]])"), "");
    if (first == "table" || first == "effect") continue;
    if (!first.empty()) table = effects ? "effects." + first : first;
    rows[table] += line.substr(end) + "\n";
  }
  return rows;
}

/// Every default the parser took for (table, key), over all the scenes read.
using Defaults = std::map<std::pair<std::string, std::string>, std::set<std::string>>;

/// The literal at the start of a reference default, "(0.4)", "(`\"wcsph\"`)", "(true)",
/// "([0, -9.81, 0] m/s)", "(0 kg/m: none)", as the parser writes it; "" for words ("(all)").
std::string literalDefault(std::string d) {
  d = std::regex_replace(d, std::regex("`"), "");
  d = std::regex_replace(d, std::regex("\u2212"), "-");  // the reference's minus sign
  std::smatch m;
  if (std::regex_search(d, m, std::regex(R"(^"[^"]*"$)"))) return m.str();  // one string, not a list of choices
  if (std::regex_search(d, m, std::regex(R"(^(true|false)\b)"))) return m.str();
  // Units ("(1/s)"), a count per entry ("(1 each)") and empty lists of names are no literal.
  if (std::regex_search(d, std::regex(R"(^[0-9.]+ ?/|^[0-9.]+ each|^\[\])"))) return "";
  if (std::regex_search(d, m, std::regex(R"(^\[([-0-9.e, ]*)\])"))) {
    std::string out;
    std::string list = m[1].str();
    const std::regex number(R"(-?[0-9.]+(e-?[0-9]+)?)");
    std::sregex_iterator it(list.begin(), list.end(), number), end;
    for (; it != end; ++it) out += (out.empty() ? "" : ", ") + fmt::format("{:g}", std::stod(it->str()));
    return "[" + out + "]";
  }
  // A number, unless it starts a range ("1-4"): the reference gives ranges in parentheses too.
  if (std::regex_search(d, m, std::regex(R"(^-?[0-9.]+(e-?[0-9]+)?\s*)")) && d.compare(size_t(m.length()), 3, "\u2013") != 0)
    return fmt::format("{:g}", std::stod(m.str()));
  return "";
}

bool mentions(const std::string& row, const std::string& key) {
  return std::regex_search(row, std::regex("(^|[^a-z_])" + key + "([^a-z_]|$)"));
}

}  // namespace

TEST(SceneReference, EveryKeyTheParserReadsIsInTheReference) {
  std::ifstream f(MF_TEST_DATA_DIR "/../docs/scene_reference.md");
  ASSERT_TRUE(f) << "docs/scene_reference.md";
  std::stringstream text;
  text << f.rdbuf();
  const auto rows = referenceRows(text.str());
  std::set<std::string> paths;
  for (const std::string& name : mf::embeddedSceneNames())
    for (const auto& p : mf::keyDefaultsReadBy([&] { mf::loadSceneStages(name); })) paths.insert(p.first);
  for (const auto& p : mf::keyDefaultsReadBy([&] { mf::parseSceneStages(kBase, "ref.toml"); })) paths.insert(p.first);
  std::vector<std::string> missing;
  size_t checked = 0;
  Defaults defaults;
  auto noteDefaults = [&](const std::map<std::string, std::string>& read) {
    for (const auto& [path, def] : read) defaults[tableAndKey(path)].insert(def);
  };
  for (const std::string& name : mf::embeddedSceneNames()) noteDefaults(mf::keyDefaultsReadBy([&] { mf::loadSceneStages(name); }));
  noteDefaults(mf::keyDefaultsReadBy([&] { mf::parseSceneStages(kBase, "ref.toml"); }));
  for (const mf::EffectInfo& info : mf::effectRegistry()) {
    auto note = [&](const std::string& table, const mf::EffectParam& p) {
      std::string d;
      for (Real v : p.defaults) d += (d.empty() ? "" : ", ") + fmt::format("{:g}", v);
      defaults[{table, p.key}].insert(p.defaults.empty() || p.phaseNames > 0 ? "" : p.components == 3 ? "[" + d + "]" : d);
    };
    for (const auto& p : info.params) note("effects." + info.name, p);
    for (const auto& l : info.lists)
      for (const auto& p : l.params) note("effects." + info.name, p);
  }
  for (const std::string& path : paths) {
    const auto [table, key] = tableAndKey(path);
    // The tables themselves, and the names of effects and materials (tables, not keys).
    if (table.empty() || table == "effects" || table == "render.material") continue;
    ++checked;
    const auto row = rows.find(table);
    // An effect's own keys are in its row; `enabled`, which every effect has, in [effects.NAME]'s.
    const auto generic = table.rfind("effects.", 0) == 0 ? rows.find("effects.NAME") : rows.end();
    if ((row == rows.end() || !mentions(row->second, key)) && (generic == rows.end() || !mentions(generic->second, key)))
      missing.push_back(path + " (table " + table + ")");
  }
  for (const mf::EffectInfo& info : mf::effectRegistry()) {
    const auto row = rows.find("effects." + info.name);
    auto check = [&](const std::string& key) {
      ++checked;
      if (row == rows.end() || !mentions(row->second, key)) missing.push_back("effects." + info.name + "." + key);
    };
    for (const auto& p : info.params) check(p.key);
    for (const auto& l : info.lists) {
      check(l.key);
      for (const auto& p : l.params) check(p.key);
    }
  }
  std::string list;
  for (const auto& m : missing) list += "\n  " + m;
  EXPECT_TRUE(missing.empty()) << missing.size() << " of " << checked << " keys are not in docs/scene_reference.md:" << list;
  EXPECT_GT(checked, 150u);

  // Defaults: each "`key` (literal ...)" in a row's key column against what the parser takes.
  std::vector<std::string> wrong;
  size_t compared = 0;
  for (const auto& [table, text] : rows) {
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      const size_t a = line.find('|'), b = line.find('|', a + 1);
      if (a == std::string::npos || b == std::string::npos) continue;
      const std::string keys = line.substr(a + 1, b - a - 1);
      static const std::regex keyDefault(R"(`([a-z_]+)` \(([^)]*)\))");
      std::sregex_iterator it(keys.begin(), keys.end(), keyDefault), end;
      for (; it != end; ++it) {
        const std::string key = (*it)[1], doc = literalDefault((*it)[2]);
        if (doc.empty()) continue;
        const auto found = defaults.find({table, key});
        if (found == defaults.end()) continue;  // a list's key named in its effect's row, or a shape's
        ++compared;
        if (!found->second.count(doc)) {
          std::string parser;
          for (const auto& d : found->second) parser += (parser.empty() ? "" : " | ") + (d.empty() ? "(none)" : d);
          wrong.push_back(table + "." + key + ": the reference says " + doc + ", the parser takes " + parser);
        }
      }
    }
  }
  std::string wrongList;
  for (const auto& w : wrong) wrongList += "\n  " + w;
  std::printf("  %zu keys found in the reference, %zu literal defaults compared with the parser's\n", checked, compared);
  EXPECT_TRUE(wrong.empty()) << wrong.size() << " of " << compared << " defaults in docs/scene_reference.md are wrong:" << wrongList;
  EXPECT_GT(compared, 100u);
}
