#include "scene_file.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "effect.h"
#include "scene_reader.h"

namespace mf {

std::string SceneProblem::str() const {
  const std::string where = fromOverride ? fmt::format("{} (--set)", file) : line > 0 ? fmt::format("{}:{}", file, line) : file;
  return key.empty() ? fmt::format("{}: {}", where, message) : fmt::format("{}: key '{}': {}", where, key, message);
}

namespace {
std::string joinProblems(const std::vector<SceneProblem>& ps) {
  std::string s;
  for (const auto& p : ps) s += (s.empty() ? "" : "\n") + p.str();
  return s;
}
}  // namespace

SceneError::SceneError(std::vector<SceneProblem> problems)
    : std::runtime_error(joinProblems(problems)), problems_(std::move(problems)) {}

uint64_t hashText(const std::string& text) {
  uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

int Scene::lineOf(const std::string& key) const {
  for (std::string k = key;;) {
    if (auto it = keyLines.find(k); it != keyLines.end()) return it->second;
    // The enclosing key: "fluid[0].max" -> "fluid[0]" -> "fluid".
    const size_t dot = k.rfind('.'), bracket = k.rfind('[');
    const size_t cut = dot == std::string::npos ? bracket : bracket == std::string::npos ? dot : std::max(dot, bracket);
    if (cut == std::string::npos || cut == 0) return 0;
    k = k.substr(0, cut);
  }
}

std::string checkName(const std::string& name) {
  if (name.empty()) return "must not be empty";
  if (name.size() > 64) return fmt::format("is {} characters long; at most 64", name.size());
  for (unsigned char c : name)
    if (!std::isalnum(c) && c != '_' && c != '-' && c != '.')
      return c < 32 || c > 126 ? fmt::format("contains the byte 0x{:02x}; allowed are letters, digits, '_', '-' and '.'", c)
                               : fmt::format("contains \"{}\"; allowed are letters, digits, '_', '-' and '.'", char(c));
  if (!std::isalnum(static_cast<unsigned char>(name[0]))) return "must start with a letter or digit";
  if (name.find("..") != std::string::npos) return "must not contain \"..\"";
  return "";
}

int Scene::lastFrame() const { return int(std::floor(endTime * frameRate + 1e-9)); }

int Scene::phaseIndex(const std::string& n) const {
  for (size_t i = 0; i < phases.size(); ++i)
    if (phases[i].name == n) return int(i);
  return -1;
}

const EffectSpec* Scene::effect(const std::string& n) const {
  for (const auto& e : effects)
    if (e.name == n) return &e;
  return nullptr;
}

namespace {

using scene_reading::rangeText;
using scene_reading::Reader;
using scene_reading::TableReader;
using scene_reading::readSolidsAndFluids;

// --set key=value: walks tables; [[phase]] etc. are addressed by index or by their "name".
void applyOverride(toml::table& root, const std::string& assignment, const std::string& file,
                   std::vector<SceneProblem>& problems, std::set<std::string>& overridden) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    problems.push_back({file, 0, assignment, "override must look like key=value, e.g. solver.cfl=0.3", true});
    return;
  }
  const std::string key = assignment.substr(0, eq);
  toml::table parsedValue;
  try {
    parsedValue = toml::parse("v = " + assignment.substr(eq + 1));
  } catch (const toml::parse_error&) {
    // Bare words are strings: --set solver.density_formulation=number
    parsedValue = toml::table{{"v", assignment.substr(eq + 1)}};
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string s; std::getline(ss, s, '.');) parts.push_back(s);
  if (parts.empty() || key.back() == '.' || std::find(parts.begin(), parts.end(), "") != parts.end()) {
    problems.push_back({file, 0, key, "override key has an empty part; keys look like solver.cfl or phase.water.stiffness", true});
    return;
  }
  toml::table* t = &root;
  std::string canonical;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    canonical += (canonical.empty() ? "" : ".") + parts[i];
    if (n && n->is_array_of_tables() && i + 2 < parts.size() + 1) {
      toml::array& arr = *n->as_array();
      const std::string& sel = parts[++i];
      toml::table* found = nullptr;
      for (size_t k = 0; k < arr.size(); ++k) {
        toml::table* e = arr[k].as_table();
        if (std::to_string(k) == sel || (e->contains("name") && e->get("name")->value<std::string>() == sel)) {
          found = e;
          canonical += fmt::format("[{}]", k);
        }
      }
      if (!found) {
        problems.push_back({file, 0, key, fmt::format("no [[{}]] entry with index or name '{}'", parts[i - 1], sel), true});
        return;
      }
      t = found;
      continue;
    }
    if (!n) n = t->insert_or_assign(parts[i], toml::table{}).first->second.as_table();
    if (!n->is_table()) {
      problems.push_back({file, 0, key, fmt::format("'{}' is not a table", parts[i]), true});
      return;
    }
    t = n->as_table();
  }
  t->insert_or_assign(parts.back(), *parsedValue.get("v"));
  overridden.insert(canonical.empty() ? parts.back() : canonical + "." + parts.back());
}

void readSolver(TableReader& s, SolverSettings& o) {
  o.pressureNamed = s.has("pressure");
  o.pressure = s.text("pressure", "dfsph", {"dfsph", "wcsph"}) == "dfsph" ? PressureSolverChoice::DFSPH : PressureSolverChoice::WCSPH;
  o.densityTolerance = s.number("density_tolerance", o.densityTolerance, 1e-6, 0.1, "(relative)", false);
  o.divergenceTolerance = s.number("divergence_tolerance", o.divergenceTolerance, 1e-6, 0.1, "(relative, per step)", false);
  o.maxCompression = s.number("max_compression", o.maxCompression, 1e-4, 1, "(relative)", false);
  o.maxPressureIterations = s.integer("max_pressure_iterations", o.maxPressureIterations, 2, 10000);
  o.conjugateGradient = s.text("pressure_iteration", "cg", {"cg", "jacobi"}) == "cg";
  o.particleSpacing = s.number("particle_spacing", o.particleSpacing, 1e-5, 10, "m", true, true);
  o.smoothingRatio = s.number("smoothing_ratio", o.smoothingRatio, 1.2, 4.0);
  o.density = s.text("density_formulation", "mass", {"mass", "number"}) == "number" ? DensityFormulation::Number
                                                                                    : DensityFormulation::Mass;
  o.kernel = s.text("kernel", "wendland", {"wendland", "muller2003"}) == "muller2003" ? KernelChoice::Muller2003
                                                                                     : KernelChoice::WendlandC2;
  o.clampNegativePressure = s.boolean("clamp_negative_pressure", o.clampNegativePressure);
  o.freeSurfaceCompletion = s.boolean("free_surface_completion", o.freeSurfaceCompletion);
  o.cfl = s.number("cfl", o.cfl, 0, 10, "", true);
  o.forceFactor = s.number("force_factor", o.forceFactor, 0, 10, "", true);
  o.maxDt = s.number("max_dt", o.maxDt, 1e-9, 1, "s", true);
  o.minDt = s.number("min_dt", o.minDt, 1e-14, 1, "s", true);
  o.boundarySpacingRatio = s.number("boundary_spacing_ratio", o.boundarySpacingRatio, 0.2, 1.5);
  o.reorderInterval = s.integer("reorder_interval", o.reorderInterval, 1, 1000);
  o.maxMoveRatio = s.number("max_move_ratio", o.maxMoveRatio, 0, 4, "", true);
  o.maxDensityError = s.number("max_density_error", o.maxDensityError, 0, 100, "", true);
  o.maxRetries = s.integer("max_retries", o.maxRetries, 0, 40);
}

/// A problem with `key` of the table `t`: at the key's line if it is given, else the table's.
void reportAt(Reader& r, TableReader& t, const std::string& key, const std::string& message) {
  if (t.has(key)) r.problem(t.node(key), t.path(key), message);
  else r.problemAt(t.line(), t.path(key), message);
}

/// One effect parameter into `out`: a number, a vector, or phase names (stored as indices).
void readEffectParam(Reader& r, TableReader& t, const EffectParam& p, const Scene& sc, ParamValues& out) {
  const bool required = p.defaults.empty();
  if (p.phaseNames > 0) {
    std::vector<Real> indices(size_t(p.phaseNames), -1);
    const toml::node* n = t.node(p.key);
    std::vector<std::string> names;
    if (n && p.phaseNames == 1 && n->is_string()) names.push_back(*n->value<std::string>());
    if (n && p.phaseNames > 1 && n->is_array())
      for (const toml::node& e : *n->as_array()) names.push_back(e.value<std::string>().value_or(""));
    std::string known;
    for (const auto& ph : sc.phases) known += (known.empty() ? "\"" : ", \"") + ph.name + "\"";
    const std::string what = p.phaseNames == 1 ? "a phase name" : fmt::format("an array of {} phase names", p.phaseNames);
    if (!n) {
      if (required) r.problemAt(t.line(), t.path(p.key), fmt::format("missing; {} (defined: {})", what, known));
    } else if (names.size() != size_t(p.phaseNames)) {
      r.problem(n, t.path(p.key), fmt::format("expected {} (defined: {})", what, known));
    } else {
      for (size_t k = 0; k < names.size(); ++k) {
        indices[k] = sc.phaseIndex(names[k]);
        if (indices[k] < 0) r.problem(n, t.path(p.key), fmt::format("unknown phase \"{}\"; defined: {}", names[k], known));
      }
    }
    out.params[p.key] = indices;
    return;
  }
  const std::vector<Real> def = required ? std::vector<Real>(size_t(p.components), 0) : p.defaults;
  if (p.components == 1 && p.whole) out.params[p.key] = {Real(t.integer(p.key, int(def.at(0)), p.lo, p.hi, p.unit))};
  else if (p.components == 1) out.params[p.key] = {t.number(p.key, def.at(0), p.lo, p.hi, p.unit, false, required)};
  else out.params[p.key] = t.numbers(p.key, size_t(p.components), def, p.lo, p.hi, p.unit, required);
}

}  // namespace

namespace {
/// toml++ parses nested tables, arrays and dotted keys recursively: tens of thousands of levels
/// overflow the stack. No scene nests more than a few levels, so deeper text is refused first.
/// Returns the first line nesting deeper than `limit`, or 0. Strings and comments are skipped.
int lineNestedDeeperThan(const std::string& text, int limit) {
  int line = 1, depth = 0, dots = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line, dots = 0;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool triple = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string close = triple ? std::string(3, c) : std::string(1, c);
      size_t j = i + close.size();
      for (; j < text.size(); ++j) {
        if (c == '"' && text[j] == '\\') {
          ++j;
          continue;
        }
        if (text[j] == '\n') {
          if (!triple) break;
          ++line;
        }
        if (text.compare(j, close.size(), close) == 0) break;
      }
      i = j + close.size() - 1;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return line;
    } else if (c == ']' || c == '}') {
      depth = std::max(0, depth - 1);
    } else if (c == '.' && !(i > 0 && std::isdigit(static_cast<unsigned char>(text[i - 1])))) {
      if (++dots > limit) return line;
    }
  }
  return 0;
}
}  // namespace

namespace scene_reading {

SceneDocument parseDocument(const std::string& text, const std::string& sourceName, const std::vector<std::string>& overrides) {
  constexpr int kMaxNesting = 64;
  if (const int line = lineNestedDeeperThan(text, kMaxNesting))
    throw SceneError({{sourceName, line, "", fmt::format("tables, arrays or dotted keys nested deeper than {} levels", kMaxNesting)}});
  toml::table root;
  try {
    root = toml::parse(text, sourceName);
  } catch (const toml::parse_error& e) {
    throw SceneError({{sourceName, int(e.source().begin.line), "", std::string(e.description())}});
  }
  std::vector<SceneProblem> overrideProblems;
  std::set<std::string> overridden;
  for (const std::string& o : overrides) applyOverride(root, o, sourceName, overrideProblems, overridden);
  if (!overrideProblems.empty()) throw SceneError(overrideProblems);

  return SceneDocument{std::move(root), Reader(sourceName, overridden), sourceName};
}

Scene readSimulation(SceneDocument& doc) {
  const toml::table& root = doc.root;
  Reader& r = doc.reader;
  Scene sc;
  sc.sourceFile = doc.sourceName;
  {
    std::ostringstream os;
    os << root;
    sc.sourceText = os.str();
    // What the simulation depends on: everything but the later stages' settings, so that
    // re-surfacing with other settings does not invalidate the particles and checkpoints.
    toml::table simulationPart = root;
    simulationPart.erase("surfacing");
    simulationPart.erase("render");
    std::ostringstream ss;
    ss << simulationPart;
    sc.simulationHash = hashText(ss.str());
  }
  {
    TableReader top(r, &root, "");
    TableReader scene(r, top.table("scene"), "scene");
    if (!top.has("scene")) r.problemAt(1, "scene", "missing [scene] table (name, end_time, frame_rate, domain_min, domain_max)");
    sc.name = scene.text("name", "unnamed");
    r.name(scene.node("name"), "scene.name", sc.name);
    sc.endTime = scene.number("end_time", sc.endTime, 0, 1e6, "s", true);
    sc.frameRate = scene.number("frame_rate", sc.frameRate, 0, 1e4, "frames/s", true);
    sc.domainMin = scene.vec3("domain_min", {}, -1e6, 1e6, "m", true);
    sc.domainMax = scene.vec3("domain_max", {}, -1e6, 1e6, "m", true);
    scene.requireIncreasing(sc.domainMin, sc.domainMax, "domain_max", "scene.domain_min");

    TableReader solver(r, top.table("solver"), "solver");
    if (!top.has("solver")) r.problemAt(1, "solver", "missing [solver] table (at least particle_spacing)");
    readSolver(solver, sc.solver);
    if (sc.solver.minDt > sc.solver.maxDt) r.problem(solver.node("min_dt"), "solver.min_dt", "must not exceed solver.max_dt");

    scene.strings("periodic", "axes, e.g. [\"x\", \"z\"]", [&](const toml::node& e, const std::string& a) {
      const int axis = a == "x" ? 0 : a == "y" ? 1 : a == "z" ? 2 : -1;
      if (axis < 0) r.problem(&e, "scene.periodic", "\"" + a + "\" is not one of \"x\", \"y\", \"z\"");
      else if (sc.periodicAxes & (1u << axis)) r.problem(&e, "scene.periodic", "\"" + a + "\" is listed twice");
      else {
        sc.periodicAxes = uint8_t(sc.periodicAxes | (1u << axis));
        // The minimum image is unique only while a period exceeds two support radii.
        const Real L = sc.domainMax[axis] - sc.domainMin[axis];
        const Real h = sc.solver.smoothingRatio * sc.solver.particleSpacing;
        if (L > 0 && h > 0 && !(L > 2 * h))
          r.problem(&e, "scene.periodic", fmt::format("the domain is {:g} m along {}; a periodic axis needs more than two support radii ({:g} m)", L, a, 2 * h));
      }
    });

    std::map<std::string, std::vector<std::pair<int, std::string>>> phaseKeyLines;  // effect-specific [[phase]] keys given, and where
    const auto phaseTables = top.tables("phase");
    if (phaseTables.empty()) r.problemAt(1, "phase", "at least one [[phase]] is required");
    if (phaseTables.size() > 64) r.problemAt(1, "phase", fmt::format("{} phases; at most 64", phaseTables.size()));
    for (size_t k = 0; k < phaseTables.size(); ++k) {
      TableReader t(r, phaseTables[k], fmt::format("phase[{}]", k));
      PhaseSpec p;
      p.name = t.text("name", fmt::format("phase{}", k), {}, true);
      if (t.has("name")) r.name(t.node("name"), t.path("name"), p.name);
      p.restDensity = t.number("rest_density", p.restDensity, 1e-3, 1e6, "kg/m^3", false, true);
      // Only the weakly compressible solver has a stiffness; DFSPH's pressure is implicit.
      const bool wcsph = sc.solver.pressure == PressureSolverChoice::WCSPH;
      p.stiffness = t.number("stiffness", p.stiffness, 0, 1e10, "m^2/s^2", true, wcsph);
      if (!sc.solver.pressureNamed && t.has("stiffness")) r.problem(t.node("stiffness"), t.path("stiffness"), kWcsphKeyUnnamed);
      p.viscosity = t.number("viscosity", p.viscosity, 0, 1e7, "Pa s");
      p.particleMass = t.number("particle_mass", p.particleMass, 0, 1e6, "kg (0 = from rest density and spacing)");
      p.addedDensity = t.number("added_density", p.addedDensity, 0, 1e6, "kg/m^3");
      p.interfaceColour = t.number("interface_colour", p.interfaceColour, -10, 10);
      p.surfaceColour = t.number("surface_colour", p.surfaceColour, 0, 1, "(1 liquid, 0 gas)");
      p.surfaceTension = t.number("surface_tension", p.surfaceTension, 0, 1e4, "N/m");
      p.thermalDiffusivity = t.number("thermal_diffusivity", p.thermalDiffusivity, 0, 10, "m^2/s");
      p.dyeDiffusivity = t.number("dye_diffusivity", p.dyeDiffusivity, 0, 10, "m^2/s");
      p.thermalExpansion = t.number("thermal_expansion", p.thermalExpansion, 0, 1, "1/K");
      p.referenceTemperature = t.number("reference_temperature", p.referenceTemperature, -273.15, 1e4, "deg C");
      for (const char* key : {"interface_colour", "surface_colour", "surface_tension", "thermal_diffusivity",
                              "dye_diffusivity", "thermal_expansion", "reference_temperature"})
        if (t.has(key)) phaseKeyLines[key].push_back({int(t.node(key)->source().begin.line), t.path(key)});
      if (sc.phaseIndex(p.name) >= 0) r.problemAt(t.line(), t.path("name"), fmt::format("duplicate phase name \"{}\"", p.name));
      sc.phases.push_back(p);
    }

    readSolidsAndFluids(r, top, sc);
    // A box container wraps with the domain: it must reach the periodic faces (its walls across
    // a periodic axis are not sampled, and a narrower box would still clamp there).
    for (size_t k = 0; k < sc.solids.size(); ++k)
      for (int a = 0; a < 3; ++a) {
        const SolidSpec& so = sc.solids[k];
        if (!sc.periodic().wraps(a) || so.shape != SolidSpec::Shape::Box) continue;
        if (so.min[a] <= sc.domainMin[a] && so.max[a] >= sc.domainMax[a]) continue;
        const std::string key = fmt::format("solid[{}].min", k);
        r.problemAt(r.lines.count(key) ? r.lines[key] : 0, key,
                    fmt::format("scene.periodic wraps {}: a box must reach the domain's faces there ({:g} to {:g} m)",
                                "xyz"[a], sc.domainMin[a], sc.domainMax[a]));
      }

    // Effects: a table per enabled effect, [effects.NAME], with that effect's own keys.
    const toml::table* et = top.table("effects");
    if (et) {
      TableReader effectsReader(r, et, "effects");
      for (const EffectInfo& info : effectRegistry()) {
        if (!et->contains(info.name)) continue;
        const toml::table* effectTable = effectsReader.table(info.name);
        TableReader t(r, effectTable, "effects." + info.name);
        if (!t.boolean("enabled", true)) {
          // Switched off (e.g. --set effects.NAME.enabled=false): its other keys are not errors.
          if (effectTable)
            for (auto&& [k, v] : *effectTable) t.node(std::string(k.str()));
          continue;
        }
        EffectSpec spec;
        spec.name = info.name;
        const size_t effectProblems = r.problems.size();
        for (const EffectParam& p : info.params) readEffectParam(r, t, p, sc, spec);
        for (const EffectList& l : info.lists) {
          auto& entries = spec.lists[l.key];
          const auto tables = t.tables(l.key);
          for (size_t k = 0; k < tables.size(); ++k) {
            TableReader e(r, tables[k], fmt::format("effects.{}.{}[{}]", info.name, l.key, k));
            ParamValues values;
            const size_t entryProblems = r.problems.size();
            for (const EffectParam& p : l.params) readEffectParam(r, e, p, sc, values);
            // Every box of every effect (sources, nozzles, sinks): min < max in each component.
            if (r.problems.size() == entryProblems && values.params.count("min") && values.params.count("max") &&
                values.params["min"].size() == 3 && values.params["max"].size() == 3)
              for (int a = 0; a < 3; ++a)
                if (!(values.params["min"][size_t(a)] < values.params["max"][size_t(a)])) {
                  reportAt(r, e, "max", "must be greater than min in every component");
                  break;
                }
            if (l.check && r.problems.size() == entryProblems)  // only on values that passed their ranges
              for (const auto& [key, message] : l.check(values)) reportAt(r, e, key, message);
            entries.push_back(values);
          }
        }
        if (info.check && r.problems.size() == effectProblems)
          for (const auto& [key, message] : info.check(spec, sc)) reportAt(r, t, key, message);
        sc.effects.push_back(spec);
      }
      for (auto&& [k, v] : *et)
        if (!findEffect(std::string(k.str()))) {
          std::string known;
          for (const EffectInfo& info : effectRegistry()) known += (known.empty() ? "" : ", ") + info.name;
          effectsReader.node(std::string(k.str()));  // reported here, not again as unknown key
          r.problem(&v, "effects." + std::string(k.str()), fmt::format("unknown effect; known effects: {}", known));
        }
    }
    // A material constant that no enabled effect reads is most likely a forgotten [effects.X].
    for (const auto& [key, lines] : phaseKeyLines) {
      bool used = false;
      std::string users;
      for (const EffectInfo& info : effectRegistry())
        if (std::find(info.phaseKeys.begin(), info.phaseKeys.end(), key) != info.phaseKeys.end()) {
          users += (users.empty() ? "[effects." : " or [effects.") + info.name + "]";
          used |= sc.effect(info.name) != nullptr;
        }
      if (!used)
        for (const auto& [line, path] : lines) r.problemAt(line, path, "has no effect unless " + users + " is enabled");
    }
    // The later stages' tables are theirs (surfacing/settings.h, render/settings.h): here
    // only their type is checked.
    top.table("surfacing");
    top.table("render");
  }
  return sc;
}

void finishScene(SceneDocument& doc, Scene& scene) {
  if (!doc.reader.problems.empty()) throw SceneError(doc.reader.problems);
  scene.keyLines = doc.reader.lines;
  scene.overriddenKeys = doc.reader.overridden();
}

}  // namespace scene_reading

Scene parseScene(const std::string& text, const std::string& sourceName, const std::vector<std::string>& overrides) {
  scene_reading::SceneDocument doc = scene_reading::parseDocument(text, sourceName, overrides);
  Scene sc = scene_reading::readSimulation(doc);
  scene_reading::finishScene(doc, sc);
  return sc;
}

SceneSource readSceneSource(const std::string& pathOrName) {
  const bool isPath = pathOrName.find('/') != std::string::npos ||
                      (pathOrName.size() > 5 && pathOrName.compare(pathOrName.size() - 5, 5, ".toml") == 0);
  if (!isPath) {
    if (const char* text = embeddedSceneText(pathOrName)) return {text, "<embedded:" + pathOrName + ">"};
    std::string names;
    for (const auto& n : embeddedSceneNames()) names += (names.empty() ? "" : ", ") + n;
    throw SceneError({{pathOrName, 0, "",
                       fmt::format("no embedded scene of that name (embedded: {}); a scene file is given as a path with '/' "
                                   "or a name ending in .toml, e.g. ./{}.toml", names, pathOrName)}});
  }
  constexpr uintmax_t kMaxSceneBytes = 1 << 20;  // scene files are a few KiB; this is no scene
  std::error_code ec;
  const auto status = std::filesystem::status(pathOrName, ec);
  if (ec || !std::filesystem::exists(status)) throw SceneError({{pathOrName, 0, "", "cannot open scene file: no such file"}});
  if (std::filesystem::is_directory(status)) throw SceneError({{pathOrName, 0, "", "is a folder, not a scene file"}});
  if (!std::filesystem::is_regular_file(status)) throw SceneError({{pathOrName, 0, "", "is not a regular file"}});
  const uintmax_t size = std::filesystem::file_size(pathOrName, ec);
  if (ec || size > kMaxSceneBytes)
    throw SceneError({{pathOrName, 0, "", fmt::format("the file has {} bytes; a scene file may have at most {} (1 MiB)", size, kMaxSceneBytes)}});
  std::ifstream in(pathOrName, std::ios::binary);
  if (!in) throw SceneError({{pathOrName, 0, "", "cannot open scene file"}});
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (text.find('\0') != std::string::npos) throw SceneError({{pathOrName, 0, "", "contains NUL bytes: not a TOML text file"}});
  return {text, pathOrName};
}

Scene loadScene(const std::string& pathOrName, const std::vector<std::string>& overrides) {
  const SceneSource source = readSceneSource(pathOrName);
  return parseScene(source.text, source.name, overrides);
}

std::map<std::string, std::string> keyDefaultsReadBy(const std::function<void()>& parse) {
  std::map<std::string, std::string> keys;
  scene_reading::keyLog() = &keys;
  try {
    parse();
  } catch (...) {
    scene_reading::keyLog() = nullptr;
    throw;
  }
  scene_reading::keyLog() = nullptr;
  return keys;
}

}  // namespace mf
