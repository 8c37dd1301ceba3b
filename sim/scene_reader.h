// The machinery behind scene files, shared by every stage's reader (sim/scene_file.cpp,
// surfacing/settings_file.cpp, render/settings_file.cpp): a Reader collects every problem with its
// file, line and key; a TableReader reads one table's keys with their ranges and reports the keys
// nobody asked for. toml++ types appear here, not in scene_file.h.
#pragma once

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene_file.h"

namespace mf::scene_reading {

inline std::string rangeText(Real lo, Real hi, bool loOpen, const std::string& unit) {
  auto num = [](Real v) { return std::fabs(v) >= 1e299 ? std::string(v < 0 ? "-inf" : "inf") : fmt::format("{:g}", v); };
  return fmt::format("{}{}, {}]{}", loOpen ? "(" : "[", num(lo), num(hi), unit.empty() ? "" : " " + unit);
}

/// Collects problems while reading; knows where each value came from.
class Reader {
 public:
  Reader(std::string file, std::set<std::string> overridden)
      : file_(std::move(file)), overridden_(std::move(overridden)) {}

  void problem(const toml::node* node, const std::string& key, const std::string& msg) {
    const bool over = overridden_.count(key) > 0;
    const int line = node && !over ? int(node->source().begin.line) : 0;
    problems.push_back({file_, line, key, msg, over});
  }
  void problemAt(int line, const std::string& key, const std::string& msg) {
    const bool over = overridden_.count(key) > 0;
    problems.push_back({file_, over ? 0 : line, key, msg, over});
  }
  void noteLine(const std::string& key, const toml::node* node) {
    if (node && node->source().begin.line > 0 && !overridden_.count(key)) lines[key] = int(node->source().begin.line);
  }
  /// A name that becomes a file or folder name: checked by checkName.
  void name(const toml::node* node, const std::string& key, const std::string& value) {
    if (const std::string why = checkName(value); !why.empty())
      problem(node, key, fmt::format("name \"{}\" {}", value.size() > 40 ? value.substr(0, 40) + "..." : value, why));
  }

  std::vector<SceneProblem> problems;
  std::map<std::string, int> lines;
  const std::set<std::string>& overridden() const { return overridden_; }

 private:
  std::string file_;
  std::set<std::string> overridden_;
};

/// Where TableReader notes every key path it is asked for, with the default it would take
/// ("" where it has no literal one), when set (keyDefaultsReadBy, scene_file.h).
inline std::map<std::string, std::string>*& keyLog() {
  static std::map<std::string, std::string>* log = nullptr;
  return log;
}

/// Reads the keys of one table; reports unknown keys when done.
class TableReader {
 public:
  TableReader(Reader& r, const toml::table* t, std::string prefix) : r_(r), t_(t), prefix_(std::move(prefix)) {
    if (t_ && !prefix_.empty()) r_.noteLine(prefix_, t_);
  }
  ~TableReader() {
    if (!t_) return;
    for (auto&& [k, v] : *t_)
      if (!used_.count(std::string(k.str())))
        r_.problem(&v, path(std::string(k.str())), "unknown key (misspelt?)");
  }
  std::string path(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  int line() const { return t_ ? int(t_->source().begin.line) : 0; }
  const toml::node* node(const std::string& key) {
    used_.insert(key);
    if (keyLog()) keyLog()->emplace(path(key), "");
    const toml::node* n = t_ ? t_->get(key) : nullptr;
    r_.noteLine(path(key), n);
    return n;
  }
  bool has(const std::string& key) const { return t_ && t_->contains(key); }
  Reader& reader() { return r_; }

  Real number(const std::string& key, Real def, Real lo, Real hi, const std::string& unit = "",
              bool loOpen = false, bool required = false) {
    const toml::node* n = node(key);
    logDefault(key, required ? "" : fmt::format("{:g}", def));
    if (!n) {
      if (required) r_.problemAt(line(), path(key), fmt::format("missing; a number in {}", rangeText(lo, hi, loOpen, unit)));
      return def;
    }
    auto v = n->value<double>();
    if (!v || n->is_boolean()) {
      r_.problem(n, path(key), fmt::format("expected a number in {}", rangeText(lo, hi, loOpen, unit)));
      return def;
    }
    if (!std::isfinite(*v) || *v > hi || *v < lo || (loOpen && *v == lo)) {
      r_.problem(n, path(key), fmt::format("value {:g} outside the allowed range {}", *v, rangeText(lo, hi, loOpen, unit)));
      return def;
    }
    return *v;
  }

  /// A whole number (a count, a size in pixels, a choice) in [lo, hi].
  int integer(const std::string& key, int def, Real lo, Real hi, const std::string& unit = "") {
    const Real v = number(key, def, lo, hi, unit);
    if (v != std::floor(v)) {
      r_.problem(node(key), path(key), fmt::format("value {:g} is not a whole number; expected one in {}", v, rangeText(lo, hi, false, unit)));
      return def;
    }
    return int(v);
  }

  std::vector<Real> numbers(const std::string& key, size_t count, std::vector<Real> def, Real lo, Real hi,
                            const std::string& unit = "", bool required = false) {
    const toml::node* n = node(key);
    if (!required) {
      std::string d;
      for (Real v : def) d += (d.empty() ? "" : ", ") + fmt::format("{:g}", v);
      logDefault(key, def.empty() ? "" : "[" + d + "]");
    }
    const std::string what = count == 0 ? "an array of numbers" : fmt::format("an array of {} numbers", count);
    if (!n) {
      if (required) r_.problemAt(line(), path(key), fmt::format("missing; {} in {}", what, rangeText(lo, hi, false, unit)));
      return def;
    }
    const toml::array* a = n->as_array();
    if (!a || (count > 0 && a->size() != count) || a->empty()) {
      r_.problem(n, path(key), fmt::format("expected {}", what));
      return def;
    }
    std::vector<Real> out;
    for (const toml::node& e : *a) {
      auto v = e.value<double>();
      if (!v || e.is_boolean() || !std::isfinite(*v) || *v < lo || *v > hi) {
        r_.problem(&e, path(key), fmt::format("each component must be a number in {}", rangeText(lo, hi, false, unit)));
        return def;
      }
      out.push_back(*v);
    }
    return out;
  }

  Vec3 vec3(const std::string& key, Vec3 def, Real lo = -1e6, Real hi = 1e6, const std::string& unit = "m",
            bool required = false) {
    auto v = numbers(key, 3, {def.x, def.y, def.z}, lo, hi, unit, required);
    return {v[0], v[1], v[2]};
  }

  bool boolean(const std::string& key, bool def) {
    const toml::node* n = node(key);
    logDefault(key, def ? "true" : "false");
    if (!n) return def;
    if (!n->is_boolean()) {
      r_.problem(n, path(key), "expected true or false");
      return def;
    }
    return *n->value<bool>();
  }

  std::string text(const std::string& key, const std::string& def, const std::vector<std::string>& allowed = {},
                   bool required = false) {
    const toml::node* n = node(key);
    logDefault(key, required || def.empty() ? "" : "\"" + def + "\"");
    std::string choices;
    for (const auto& a : allowed) choices += (choices.empty() ? "" : ", ") + ("\"" + a + "\"");
    if (!n) {
      if (required) r_.problemAt(line(), path(key), allowed.empty() ? "missing; a string" : "missing; one of " + choices);
      return def;
    }
    if (!n->is_string()) {
      r_.problem(n, path(key), allowed.empty() ? "expected a string" : "expected one of " + choices);
      return def;
    }
    std::string s = *n->value<std::string>();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
      r_.problem(n, path(key), fmt::format("\"{}\" is not one of {}", s, choices));
      return def;
    }
    return s;
  }

  /// Reports `maxKey` unless min < max in every component.
  void requireIncreasing(const Vec3& lo, const Vec3& hi, const std::string& maxKey, const std::string& minKey) {
    for (int a = 0; a < 3; ++a)
      if (!(lo[a] < hi[a])) {
        r_.problem(node(maxKey), path(maxKey), "must be greater than " + minKey + " in every component");
        return;
      }
  }

  /// An array of strings (`expected` says of what, for the message): `each(element, value)` for
  /// each element, in order (a non-string element's value is ""). False if the key is absent.
  template <class Each>
  bool strings(const std::string& key, const std::string& expected, Each each) {
    if (!has(key)) return false;
    const toml::node* n = node(key);
    if (const toml::array* a = n->as_array())
      for (const toml::node& e : *a) each(e, e.value<std::string>().value_or(""));
    else
      r_.problem(n, path(key), "expected an array of " + expected);
    return true;
  }

  /// An array of phase names (`key`) into their indices in `scene`, appended to `out`: unknown
  /// and repeated names are problems, and so is a phase for which `refuse` gives a reason.
  /// False if the key is absent.
  template <class Refuse>
  bool phaseNames(const std::string& key, const Scene& scene, std::vector<uint16_t>& out, Refuse refuse) {
    return strings(key, "phase names", [&](const toml::node& e, const std::string& name) {
      const int pi = scene.phaseIndex(name);
      std::string why;
      if (pi < 0) why = "unknown phase \"" + e.value<std::string>().value_or("?") + "\"";
      else if (std::find(out.begin(), out.end(), uint16_t(pi)) != out.end()) why = "phase \"" + name + "\" is listed twice";
      else why = refuse(pi);
      if (why.empty()) out.push_back(uint16_t(pi));
      else r_.problem(&e, path(key), why);
    });
  }

  const toml::table* table(const std::string& key) {
    const toml::node* n = node(key);
    if (n && !n->is_table()) r_.problem(n, path(key), "expected a table");
    return n ? n->as_table() : nullptr;
  }

  /// Array of tables ([[key]]); reports a wrong type.
  std::vector<const toml::table*> tables(const std::string& key) {
    std::vector<const toml::table*> out;
    const toml::node* n = node(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) {
      r_.problem(n, path(key), fmt::format("expected an array of tables ([[{}]])", key));
      return out;
    }
    for (const toml::node& e : *a) {
      if (!e.is_table()) r_.problem(&e, path(key), fmt::format("expected an array of tables ([[{}]])", key));
      else out.push_back(e.as_table());
    }
    return out;
  }

 private:
  void logDefault(const std::string& key, const std::string& def) {
    if (keyLog()) (*keyLog())[path(key)] = def;
  }
  Reader& r_;
  const toml::table* t_;
  std::string prefix_;
  std::set<std::string> used_;
};

/// [[solid]] and [[fluid]] (with [[fluid.subtract]]), after [[phase]] is read.
void readSolidsAndFluids(Reader& r, TableReader& top, Scene& sc);
/// A solid's shape keys (shape, open_top, min/max, base/radius/height, profile): the
/// containers' and the render stage's props.
void readShape(Reader& r, TableReader& t, SolidSpec& s);

/// A scene file parsed, with its --set overrides applied: the document every stage reads its own
/// tables from, and the reader that collects all their problems.
struct SceneDocument {
  toml::table root;
  Reader reader;
  std::string sourceName;
  /// A later stage's table ("surfacing", "render"), or nullptr (its type is checked by
  /// readSimulation).
  const toml::table* stageTable(const char* name) const { return root.get_as<toml::table>(name); }
};

/// Parses `text` and applies `overrides`; throws SceneError for a syntax or an override problem.
SceneDocument parseDocument(const std::string& text, const std::string& sourceName, const std::vector<std::string>& overrides);
/// The simulation's tables of `doc`; every problem goes to doc.reader.
Scene readSimulation(SceneDocument& doc);
/// After every stage has read its tables: throws SceneError listing every problem, or notes in
/// `scene` where each key was given.
void finishScene(SceneDocument& doc, Scene& scene);

}  // namespace mf::scene_reading
