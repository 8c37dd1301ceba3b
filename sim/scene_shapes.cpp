// [[solid]] and [[fluid]] of a scene file: the containers, and the fluid blocks seeded in them
// (shapes, subtracted regions, mixed phases, the initial state).
#include <fmt/format.h>

#include <cmath>

#include "scene_reader.h"

namespace mf::scene_reading {

namespace {

/// A box's keys (min, max: required, increasing), for fluid regions and solids alike.
void readBoxKeys(TableReader& t, Vec3& min, Vec3& max) {
  min = t.vec3("min", {}, -1e6, 1e6, "m", true);
  max = t.vec3("max", {}, -1e6, 1e6, "m", true);
  t.requireIncreasing(min, max, "max", "min");
}

/// A cylinder's keys (base, radius, height: required, radius and height above 0).
void readCylinderKeys(TableReader& t, Vec3& base, Real& radius, Real& height) {
  base = t.vec3("base", {}, -1e6, 1e6, "m", true);
  radius = t.number("radius", 1, 0, 1e6, "m", true, true);
  height = t.number("height", 1, 0, 1e6, "m", true, true);
}

/// shape = "box" (min, max), "sphere" (centre, radius), "ellipsoid" (centre, radii) or
/// "cylinder" (base, radius, height, axis = "x" | "y" | "z").
void readRegion(TableReader& t, FluidRegion& f) {
  const std::string shape = t.text("shape", "box", {"box", "sphere", "ellipsoid", "cylinder"});
  if (shape == "box") {
    f.shape = FluidRegion::Shape::Box;
    readBoxKeys(t, f.min, f.max);
  } else if (shape == "sphere") {
    f.shape = FluidRegion::Shape::Sphere;
    f.centre = t.vec3("centre", {}, -1e6, 1e6, "m", true);
    f.radius = t.number("radius", 1, 0, 1e6, "m", true, true);
  } else if (shape == "ellipsoid") {
    f.shape = FluidRegion::Shape::Ellipsoid;
    f.centre = t.vec3("centre", {}, -1e6, 1e6, "m", true);
    f.radii = t.vec3("radii", {1, 1, 1}, 1e-6, 1e6, "m", true);
  } else {
    f.shape = FluidRegion::Shape::Cylinder;
    readCylinderKeys(t, f.base, f.radius, f.height);
    const std::string axis = t.text("axis", "y", {"x", "y", "z"});
    f.axis = axis == "x" ? 0 : axis == "y" ? 1 : 2;
  }
}

}  // namespace

/// See scene_reader.h.
void readShape(Reader& r, TableReader& t, SolidSpec& s) {
  const std::string shape = t.text("shape", "box", {"box", "cylinder", "revolution"}, true);
  s.openTop = t.boolean("open_top", false);
  if (shape == "box") {
    s.shape = SolidSpec::Shape::Box;
    readBoxKeys(t, s.min, s.max);
  } else if (shape == "cylinder") {
    s.shape = SolidSpec::Shape::Cylinder;
    readCylinderKeys(t, s.base, s.radius, s.height);
  } else {
    s.shape = SolidSpec::Shape::Revolution;
    s.base = t.vec3("base", {}, -1e6, 1e6, "m", true);
    const toml::node* pn = t.node("profile");
    const toml::array* pa = pn ? pn->as_array() : nullptr;
    bool ok = pa && pa->size() >= 2 && pa->size() <= 1000;
    if (ok)
      for (const toml::node& e : *pa) {
        const toml::array* pt = e.as_array();
        if (!pt || pt->size() != 2 || !pt->get(0)->value<double>() || !pt->get(1)->value<double>() ||
            pt->get(0)->is_boolean() || pt->get(1)->is_boolean()) {
          ok = false;
          break;
        }
        s.profile.push_back({*pt->get(0)->value<double>(), *pt->get(1)->value<double>()});
      }
    for (size_t i = 0; ok && i < s.profile.size(); ++i)
      ok = std::isfinite(s.profile[i].first) && std::isfinite(s.profile[i].second) && std::fabs(s.profile[i].first) <= 1e6 &&
           s.profile[i].second >= 0 && s.profile[i].second <= 1e6 && (i == 0 || s.profile[i].first > s.profile[i - 1].first);
    if (!ok) {
      s.profile.clear();
      if (pn) r.problem(pn, t.path("profile"), "expected 2 to 1000 points [height, radius] with increasing finite heights and radii in [0, 1e6] (m)");
      else r.problemAt(t.line(), t.path("profile"), "missing; at least 2 points [height, radius] (m)");
      s.profile = {{0, 1}, {1, 1}};
    }
  }
}

/// See scene_reader.h.
void readSolidsAndFluids(Reader& r, TableReader& top, Scene& sc) {
  const auto solidTables = top.tables("solid");
  // Every solid is tested against every particle in each step: a few containers, not a scene
  // built of thousands of boxes.
  if (solidTables.size() > 100) r.problemAt(1, "solid", fmt::format("{} solids; at most 100", solidTables.size()));
  for (size_t k = 0; k < solidTables.size() && k < 100; ++k) {
    TableReader t(r, solidTables[k], fmt::format("solid[{}]", k));
    SolidSpec s;
    s.name = t.text("name", fmt::format("solid{}", k));
    if (t.has("name")) r.name(t.node("name"), t.path("name"), s.name);
    for (const SolidSpec& other : sc.solids)
      if (other.name == s.name) r.problem(t.node("name"), t.path("name"), fmt::format("duplicate solid name \"{}\"", s.name));
    readShape(r, t, s);
    sc.solids.push_back(s);
  }

  const auto fluidTables = top.tables("fluid");
  if (fluidTables.empty()) r.problemAt(1, "fluid", "at least one [[fluid]] block is required");
  if (fluidTables.size() > 1000) r.problemAt(1, "fluid", fmt::format("{} fluid blocks; at most 1000", fluidTables.size()));
  for (size_t k = 0; k < fluidTables.size() && k < 1000; ++k) {
    TableReader t(r, fluidTables[k], fmt::format("fluid[{}]", k));
    FluidBlockSpec f;
    readRegion(t, f);
    const auto cuts = t.tables("subtract");
    if (cuts.size() > 100) r.problem(t.node("subtract"), t.path("subtract"), fmt::format("{} regions; at most 100", cuts.size()));
    for (size_t c = 0; c < cuts.size() && c < 100; ++c) {
      TableReader ct(r, cuts[c], fmt::format("fluid[{}].subtract[{}]", k, c));
      FluidRegion cut;
      readRegion(ct, cut);
      f.subtract.push_back(cut);
    }
    f.velocity = t.vec3("velocity", {}, -1e4, 1e4, "m/s");
    f.seed = uint64_t(t.number("seed", 1, 0, 9.0e15));
    f.jitter = t.number("jitter", 0, 0, 0.5, "of the particle spacing");
    if (t.has("inside")) {
      const std::string solid = t.text("inside", "");
      for (size_t k2 = 0; k2 < sc.solids.size(); ++k2)
        if (sc.solids[k2].name == solid) f.insideSolid = int(k2);
      if (f.insideSolid < 0) {
        std::string known;
        for (const auto& so : sc.solids) known += (known.empty() ? "\"" : ", \"") + so.name + "\"";
        r.problem(t.node("inside"), t.path("inside"), fmt::format("unknown solid \"{}\"; defined: {}", solid, known));
      }
    }
    f.wallMargin = t.number("wall_margin", f.wallMargin, 0, 2, "spacings");
    if (t.has("wall_margin") && f.insideSolid < 0 && !t.has("inside"))
      r.problem(t.node("wall_margin"), t.path("wall_margin"), "has no effect without inside = \"<solid>\"");
    f.temperature = t.number("temperature", f.temperature, -273.15, 1e4, "deg C");
    f.dye = t.number("dye", f.dye, -1e6, 1e6);
    std::vector<std::string> names;
    if (t.has("phase")) {
      names.push_back(t.text("phase", ""));
      f.fractions = {1.0};
    } else if (t.has("phases")) {
      const toml::node* pn = t.node("phases");
      const toml::array* pa = pn->as_array();
      if (!pa || pa->empty()) r.problem(pn, t.path("phases"), "expected an array of phase names");
      else
        for (const toml::node& e : *pa) names.push_back(e.value<std::string>().value_or(""));
      f.fractions = t.numbers("fractions", names.size(), std::vector<Real>(names.size(), 1.0), 0, 1);
      Real total = 0;
      for (Real w : f.fractions) total += w;
      if (!(total > 0)) r.problem(t.node("fractions"), t.path("fractions"), "must not all be 0 (they are the phases' shares)");
    } else {
      r.problemAt(t.line(), t.path("phase"), "missing; the name of a [[phase]] (or phases = [...] with fractions)");
    }
    for (const std::string& n : names) {
      const int pi = sc.phaseIndex(n);
      if (pi < 0) {
        std::string known;
        for (const auto& p : sc.phases) known += (known.empty() ? "\"" : ", \"") + p.name + "\"";
        r.problem(t.node(t.has("phase") ? "phase" : "phases"), t.path(t.has("phase") ? "phase" : "phases"),
                  fmt::format("unknown phase \"{}\"; defined: {}", n, known));
      } else if (std::find(f.phases.begin(), f.phases.end(), uint16_t(pi)) != f.phases.end()) {
        r.problem(t.node("phases"), t.path("phases"), fmt::format("phase \"{}\" is listed twice", n));
      } else {
        f.phases.push_back(uint16_t(pi));
      }
    }
    sc.fluids.push_back(f);
  }
}

}  // namespace mf::scene_reading
