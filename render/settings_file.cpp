// [render] of a scene file: image, camera, sky, light, table, and the materials of phases and
// solids (defaults by what the effects make of each phase, so that a scene needs no [render]
// table to render well).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "blackbody.h"
#include "settings.h"
#include "sim/scene_reader.h"
#include "surfacing/settings.h"

namespace mf {

using scene_reading::readShape;
using scene_reading::Reader;
using scene_reading::TableReader;

namespace {

/// What the scene's effects make of a phase decides its default look, not its name.
enum class PhaseRole { Liquid, Gas, Flame };

/// The gas that trapped air or boiling makes, or that artificial buoyancy lifts, is a bubble;
/// the flame that heats a glass glows; every other phase is a liquid.
std::vector<PhaseRole> phaseRoles(const Scene& sc) {
  std::vector<PhaseRole> roles(sc.phases.size(), PhaseRole::Liquid);
  // A phase key the reader could not resolve holds -1, or is absent (its problem is already
  // reported): it marks nothing.
  auto phaseOf = [](const ParamValues& v, const char* key) {
    const auto it = v.params.find(key);
    return it == v.params.end() || it->second.empty() ? Real(-1) : it->second[0];
  };
  // The flame's role wins over the gas's (boiling's buoyancy lifts its flames too).
  auto mark = [&](Real phase, PhaseRole role) {
    if (!(phase >= 0 && phase < Real(roles.size()))) return;
    PhaseRole& r = roles[size_t(phase)];
    if (role == PhaseRole::Flame || r != PhaseRole::Flame) r = role;
  };
  for (const EffectSpec& e : sc.effects) {
    if (e.name == "trapped_air") mark(phaseOf(e, "air"), PhaseRole::Gas);
    if (e.name == "phase_change") mark(phaseOf(e, "vapour"), PhaseRole::Gas);
    if (e.name == "flame_heating") mark(phaseOf(e, "flame"), PhaseRole::Flame);
    if (e.name == "buoyancy")
      for (const ParamValues& gas : e.list("gas")) mark(phaseOf(gas, "phase"), PhaseRole::Gas);
  }
  return roles;
}

/// A look for each role, so that a scene needs no [render] table to render well. `liquids`
/// counts the liquids before this one: the first is clear water, the next ones dyed, so that
/// two fluids are told apart in a frame without materials.
MaterialSpec defaultPhaseMaterial(PhaseRole role, int& liquids) {
  MaterialSpec m;
  if (role == PhaseRole::Gas) {
    m.ior = 1.0;
    m.priority = 20;  // a bubble inside water wins over the water around it
  } else if (role == PhaseRole::Flame) {
    // A glowing volume with an invisible boundary (n = 1), not an opaque surface: per metre
    // about a 1 300 K flame's orange.
    m.ior = 1.0;
    m.emission = {30, 9, 1.5};
    m.priority = 5;
  } else {
    // Absorption per metre: water is faintly blue-green at 10 cm; the dyes read clearly there.
    static const Vec3 kDyes[] = {{4.0, 1.2, 0.8},     // water
                                 {0.6, 18.0, 12.0},   // red
                                 {1.0, 3.0, 25.0},    // amber
                                 {20.0, 1.0, 14.0},   // green
                                 {10.0, 28.0, 1.5}};  // violet
    m.ior = 1.33;
    m.absorption = kDyes[size_t(liquids++) % (sizeof(kDyes) / sizeof(kDyes[0]))];
  }
  return m;
}

// Lowest and highest points of a solid's outer surface (its wall thickness outside the fluid).
void solidBounds(const SolidSpec& s, Real thickness, Vec3& lo, Vec3& hi) {
  const Vec3 t(thickness, thickness, thickness);
  switch (s.shape) {
    case SolidSpec::Shape::Box: lo = s.min - t, hi = s.max + t; return;
    case SolidSpec::Shape::Cylinder: {
      const Real r = s.radius + thickness;
      lo = s.base - Vec3(r, thickness, r), hi = s.base + Vec3(r, s.height + thickness, r);
      return;
    }
    case SolidSpec::Shape::Revolution: {
      Real r = 0;
      for (const auto& pt : s.profile) r = std::max(r, pt.second);
      r += thickness;
      const Real y0 = s.profile.empty() ? 0 : s.profile.front().first, y1 = s.profile.empty() ? 0 : s.profile.back().first;
      lo = s.base + Vec3(-r, y0 - thickness, -r), hi = s.base + Vec3(r, y1 + thickness, r);
      return;
    }
  }
}

// A camera in front of [lo, hi] and a little above it (20 degrees), at the distance where the
// box's eight corners fill 90 % of the frame's tighter side.
void frameBox(const Vec3& lo, const Vec3& hi, RenderSettings& o) {
  const Vec3 c = (lo + hi) * 0.5;
  const Vec3 back = normalize(Vec3(0, std::sin(20 * kPi / 180), std::cos(20 * kPi / 180)));
  const Vec3 right = normalize(cross(Vec3(0, 1, 0), back)), up = cross(back, right);
  const Real tanV = std::tan(0.5 * o.fov * kPi / 180), tanH = tanV * Real(o.width) / Real(o.height);
  auto fits = [&](Real d) {
    for (int k = 0; k < 8; ++k) {
      const Vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
      const Vec3 q = p - (c + back * d);
      const Real z = -dot(q, back);
      if (z <= 0 || std::fabs(dot(q, right)) > 0.9 * tanH * z || std::fabs(dot(q, up)) > 0.9 * tanV * z) return false;
    }
    return true;
  };
  Real near = 0, far = 1;
  while (!fits(far) && far < 1e7) far *= 2;
  for (int it = 0; it < 50; ++it) {
    const Real mid = 0.5 * (near + far);
    (fits(mid) ? far : near) = mid;
  }
  o.lookAt = c;
  o.cameraPosition = c + back * far;
}

MaterialSpec defaultSolidMaterial() {
  MaterialSpec m;
  m.ior = 1.5;
  m.absorption = {0.4, 0.2, 0.3};
  m.priority = 100;  // glass bounds the liquid: where meshes overlap, glass wins
  return m;
}

/// `key` = { attribute = "temperature" | "dye", range = [lo, hi], colours = [[r, g, b], ...] },
/// or for an emission ramp over temperature `blackbody = Y` in place of the colours: a
/// blackbody's colour and brightness at each temperature (deg C), luminance Y at the range's top.
void readRamp(TableReader& t, const std::string& key, ColourRamp& ramp, Real maxValue, const std::string& unit) {
  const toml::table* rt = t.table(key);
  if (!rt) return;
  TableReader e(t.reader(), rt, t.path(key));
  ramp.attribute = e.text("attribute", "", {"temperature", "dye"}, true);
  const std::vector<Real> range = e.numbers("range", 2, {0, 1}, -1e6, 1e6, "(the attribute's unit)", true);
  ramp.lo = range[0], ramp.hi = range[1];
  if (!(ramp.lo < ramp.hi)) t.reader().problem(e.node("range"), e.path("range"), "expected [lo, hi] with lo < hi");
  if (key == "emission_ramp" && e.has("blackbody")) {
    const Real top = e.number("blackbody", 0, 0, maxValue, unit + " (luminance at the range's top)", true);
    if (ramp.attribute != "temperature") {
      t.reader().problem(e.node("blackbody"), e.path("blackbody"), "a blackbody ramp reads attribute = \"temperature\"");
      ramp.attribute.clear();
      return;
    }
    if (e.has("colours")) {
      t.reader().problem(e.node("colours"), e.path("colours"), "give colours or blackbody, not both");
      ramp.attribute.clear();
      return;
    }
    if (ramp.lo <= -273.15) {
      t.reader().problem(e.node("range"), e.path("range"), "a blackbody ramp's range must lie above -273.15 deg C");
      ramp.attribute.clear();
      return;
    }
    // 64 samples, piecewise linear between them: over 700-1600 deg C the visible radiance
    // changes by at most 1.47x from one sample to the next (Wien's approximation at 560 nm).
    const Real scale = top / blackbodyXyz(ramp.hi + 273.15).y;
    for (int k = 0; k < 64; ++k)
      ramp.colours.push_back(xyzToLinearSrgb(blackbodyXyz(ramp.lo + (ramp.hi - ramp.lo) * k / 63 + 273.15)) * scale);
    return;
  }
  const toml::node* cn = e.node("colours");
  const toml::array* ca = cn ? cn->as_array() : nullptr;
  if (!ca || ca->size() < 2) {
    t.reader().problemAt(e.line(), e.path("colours"), fmt::format("expected an array of at least 2 colours [r, g, b], each in [0, {:g}] {}", maxValue, unit));
    ramp.attribute.clear();
    return;
  }
  for (const toml::node& c : *ca) {
    const toml::array* rgb = c.as_array();
    bool ok = rgb && rgb->size() == 3;
    Vec3 v;
    for (size_t k = 0; ok && k < 3; ++k) {
      const auto x = (*rgb)[k].value<double>();
      ok = x && !(*rgb)[k].is_boolean() && *x >= 0 && *x <= maxValue;
      if (ok) v[int(k)] = *x;
    }
    if (!ok) {
      t.reader().problem(&c, e.path("colours"), fmt::format("each colour must be [r, g, b], each in [0, {:g}] {}", maxValue, unit));
      ramp.attribute.clear();
      return;
    }
    ramp.colours.push_back(v);
  }
}

void readMaterial(TableReader& t, MaterialSpec& m, bool solid) {
  const std::string kind = t.text("kind", "", {"dielectric", "medium", "diffuse", "emitter"});
  if (kind == "dielectric") m.kind = MaterialSpec::Kind::Dielectric;
  else if (kind == "medium") m.kind = MaterialSpec::Kind::Medium;
  else if (kind == "diffuse") m.kind = MaterialSpec::Kind::Diffuse;
  else if (kind == "emitter") m.kind = MaterialSpec::Kind::Emitter;
  m.ior = t.number("ior", m.ior, 1, 4);
  m.absorption = t.vec3("absorption", m.absorption, 0, 1e6, "1/m");
  m.scattering = t.number("scattering", m.scattering, 0, 1e6, "1/m");
  m.colour = t.vec3("colour", m.colour, 0, 1, "(albedo)");
  m.emission = t.vec3("emission", m.emission, 0, 1e6, "(relative radiance)");
  m.priority = t.integer("priority", m.priority, 0, 1000);
  if (solid) {
    m.thickness = t.number("thickness", m.thickness, 0, 10, "m", true);
    m.visible = t.boolean("visible", m.visible);
  }
  if (!solid) {
    readRamp(t, "absorption_ramp", m.absorptionRamp, 1e6, "1/m");
    readRamp(t, "emission_ramp", m.emissionRamp, 1e6, "(relative radiance per m)");
  }
}

/// [[render.camera_key]]: time (s, increasing), position, look_at (required), fov (render.fov).
/// The static camera keys then take the first key's pose (what a still export shows).
void readCameraKeys(Reader& r, TableReader& t, RenderSettings& o, bool staticCamera) {
  const auto keys = t.tables("camera_key");
  for (size_t i = 0; i < keys.size(); ++i) {
    TableReader k(r, keys[i], fmt::format("render.camera_key[{}]", i));
    CameraKey key;
    key.time = k.number("time", 0, 0, 1e9, "s", false, true);
    key.position = k.vec3("position", {}, -1e6, 1e6, "m", true);
    key.lookAt = k.vec3("look_at", {}, -1e6, 1e6, "m", true);
    key.fov = k.number("fov", o.fov, 1, 170, "degrees");
    if (!o.cameraKeys.empty() && !(key.time > o.cameraKeys.back().time))
      r.problem(k.node("time"), k.path("time"),
                fmt::format("{:g} s is not after the previous key's {:g} s: keys go in increasing time", key.time,
                            o.cameraKeys.back().time));
    if (lengthSquared(key.lookAt - key.position) == 0)
      r.problem(k.node("look_at"), k.path("look_at"), "equals position: the camera must look somewhere");
    o.cameraKeys.push_back(key);
  }
  if (keys.empty()) return;
  if (staticCamera)
    r.problemAt(keys[0]->source().begin.line, "render.camera_key",
                "give either camera_position/look_at or [[render.camera_key]], not both");
  o.cameraPosition = o.cameraKeys[0].position, o.lookAt = o.cameraKeys[0].lookAt, o.fov = o.cameraKeys[0].fov;
}

}  // namespace

RenderSettings readRenderSettings(scene_reading::SceneDocument& doc, const Scene& sc, const SurfacingSettings& surfacing) {
  Reader& r = doc.reader;
  RenderSettings o;
  int liquids = 0;
  for (PhaseRole role : phaseRoles(sc)) o.phaseMaterials.push_back(defaultPhaseMaterial(role, liquids));
  o.solidMaterials.assign(sc.solids.size(), defaultSolidMaterial());
  TableReader t(r, doc.stageTable("render"), "render");
  o.width = t.integer("width", o.width, 8, 16384, "pixels");
  o.height = t.integer("height", o.height, 8, 16384, "pixels");
  o.samples = t.integer("samples", o.samples, 1, 1e5, "per pixel");
  o.maxDepth = t.integer("max_depth", o.maxDepth, 1, 1000, "bounces");
  o.indirectClamp = t.number("indirect_clamp", o.indirectClamp, 0, 1e9, "(relative radiance; 0 = off)");
  o.regularise = t.number("regularise", o.regularise, 0, 45, "degrees (0 = off)");
  o.shutter = t.number("shutter", o.shutter, 0, 1, "of the frame interval (0 = no motion blur)");
  // The blur moves each surface by the velocity grid that surfacing writes.
  if (o.shutter > 0 && !surfacing.velocity)
    r.problem(t.node("shutter"), "render.shutter", "motion blur needs the velocity grids: set surfacing.velocity = true");
  o.sobol = t.boolean("sobol", o.sobol);
  o.adaptive = t.number("adaptive", o.adaptive, 0, 0.9, "(share of the samples)");
  o.mis = t.boolean("mis", o.mis);
  o.animatedSeed = t.boolean("animated_seed", o.animatedSeed);
  o.denoise = t.boolean("denoise", o.denoise);
  o.denoiseIterations = t.integer("denoise_iterations", o.denoiseIterations, 1, 8, "passes");
  const auto surfaced = [&](int p) {
    return std::find(surfacing.phases.begin(), surfacing.phases.end(), p) != surfacing.phases.end()
               ? std::string()
               : "phase \"" + sc.phases[size_t(p)].name + "\" is not in surfacing.phases, so it has no level set to render";
  };
  if (!t.phaseNames("phases", sc, o.phases, surfaced)) o.phases = surfacing.phases;
  const bool staticCamera = t.has("camera_position") || t.has("look_at");
  o.cameraPosition = t.vec3("camera_position", o.cameraPosition);
  o.lookAt = t.vec3("look_at", o.lookAt);
  o.fov = t.number("fov", o.fov, 1, 170, "degrees", false);
  readCameraKeys(r, t, o, staticCamera);
  const bool cameraGiven = staticCamera || !o.cameraKeys.empty();
  o.skyZenith = t.vec3("sky_zenith", o.skyZenith, 0, 1e6, "(relative radiance)");
  o.skyHorizon = t.vec3("sky_horizon", o.skyHorizon, 0, 1e6, "(relative radiance)");
  o.skyGround = t.vec3("sky_ground", o.skyHorizon * 0.25, 0, 1e6, "(relative radiance)");
  o.lightPosition = t.vec3("light_position", o.lightPosition);
  o.lightRadius = t.number("light_radius", o.lightRadius, 0, 1e6, "m");
  o.lightEmission = t.vec3("light_emission", o.lightEmission, 0, 1e9, "(relative radiance)");
  o.floor = t.boolean("floor", o.floor);
  o.checkerSize = t.number("checker_size", o.checkerSize, 0, 1e6, "m");
  if (const toml::table* mt = t.table("material")) {
    TableReader materials(r, mt, "render.material");
    for (auto&& [k, v] : *mt) {
      const std::string name(k.str());
      const toml::table* entry = materials.table(name);
      if (!entry) continue;
      TableReader e(r, entry, "render.material." + name);
      const int pi = sc.phaseIndex(name);
      int si = -1;
      for (size_t j = 0; j < sc.solids.size(); ++j)
        if (sc.solids[j].name == name) si = int(j);
      if (pi >= 0) readMaterial(e, o.phaseMaterials[pi], false);
      else if (si >= 0) readMaterial(e, o.solidMaterials[si], true);
      else {
        std::string known;
        for (const auto& p : sc.phases) known += (known.empty() ? "" : ", ") + p.name;
        for (const auto& s : sc.solids) known += (known.empty() ? "" : ", ") + s.name;
        r.problem(&v, "render.material." + name, "names no phase or solid; defined: " + known);
        for (auto&& [kk, vv] : *entry) e.node(std::string(kk.str()));  // not reported again
      }
    }
  }
  // [[render.prop]]: a solid's shape keys and a material's, opaque and diffuse unless it says.
  const auto propTables = t.tables("prop");
  if (propTables.size() > 100) r.problemAt(t.line(), "render.prop", fmt::format("{} props; at most 100", propTables.size()));
  for (size_t k = 0; k < propTables.size() && k < 100; ++k) {
    TableReader pt(r, propTables[k], fmt::format("render.prop[{}]", k));
    PropSpec prop;
    prop.shape.name = pt.text("name", fmt::format("prop{}", k));
    readShape(r, pt, prop.shape);
    prop.material.kind = MaterialSpec::Kind::Diffuse;
    readMaterial(pt, prop.material, true);
    o.props.push_back(prop);
  }
  // A ramp reads a grid that surfacing writes: its attribute must be in surfacing.attributes.
  for (size_t p = 0; p < sc.phases.size(); ++p)
    for (const auto& [key, ramp] : {std::pair<const char*, const ColourRamp*>{"absorption_ramp", &o.phaseMaterials[p].absorptionRamp},
                                    {"emission_ramp", &o.phaseMaterials[p].emissionRamp}}) {
      const auto& attrs = surfacing.attributes;
      if (!ramp->empty() && std::find(attrs.begin(), attrs.end(), ramp->attribute) == attrs.end()) {
        const std::string path = "render.material." + sc.phases[p].name + "." + key;
        r.problemAt(r.lines.count(path) ? r.lines.at(path) : 0, path,
                    "reads \"" + ramp->attribute + "\", which surfacing does not write: add it to surfacing.attributes");
      }
    }
  // The outer bounds of the solids and props: the table top sits under the lowest (the domain's
  // floor only without them: a domain reaching below the glass left it floating above the
  // table), and without camera keys the camera frames them (or the fluid blocks, without any).
  Vec3 lo(1e30, 1e30, 1e30), hi(-1e30, -1e30, -1e30);
  auto include = [&](const SolidSpec& shape, Real thickness) {
    Vec3 a, b;
    solidBounds(shape, thickness, a, b);
    lo = cwiseMin(lo, a), hi = cwiseMax(hi, b);
  };
  for (size_t j = 0; j < sc.solids.size(); ++j) include(sc.solids[j], o.solidMaterials[j].thickness);
  for (const PropSpec& prop : o.props) include(prop.shape, prop.material.thickness);
  const bool solids = !sc.solids.empty() || !o.props.empty();
  if (!solids)
    for (const FluidBlockSpec& f : sc.fluids) {
      Vec3 a, b;
      f.bounds(a, b);
      lo = cwiseMin(lo, a), hi = cwiseMax(hi, b);
    }
  o.floorHeight = t.number("floor_height", solids ? lo.y : sc.domainMin.y, -1e6, 1e6, "m");
  if (!cameraGiven && lo.x <= hi.x) {
    frameBox(lo, hi, o);
    o.cameraFraming = fmt::format("no camera_position or look_at: framing the {} [{:.3g}, {:.3g}, {:.3g}]-[{:.3g}, {:.3g}, {:.3g}] from ({:.3g}, {:.3g}, {:.3g})",
                                  solids ? "solids" : "fluid blocks", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, o.cameraPosition.x,
                                  o.cameraPosition.y, o.cameraPosition.z);
  }
  return o;
}

}  // namespace mf
