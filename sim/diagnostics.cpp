#include "diagnostics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "simulation.h"

namespace mf {

std::string tomlReal(double v) {
  std::string s = fmt::format("{:.10g}", v);
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

std::string layeredScene(double spacing, const std::string& densityFormulation, bool reference, double endTime) {
  constexpr double kLayer = 0.06;
  const std::string pressure =
      reference ? fmt::format("reference_density = 1000.0\nreference_level = {}\n", tomlReal(1.5 * kLayer)) : std::string();
  return fmt::format(R"(
[scene]
name = "layered"
end_time = {end}
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.21, 0.07]
[solver]
particle_spacing = {s}
density_formulation = "{formulation}"
max_dt = 0.002
[[phase]]
name = "light"
rest_density = 500.0
stiffness = 200.0
viscosity = 0.5
[[phase]]
name = "heavy"
rest_density = 1000.0
stiffness = 200.0
viscosity = 0.5
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.2, 0.06]
[[fluid]]
phase = "light"
min = [0.0, 0.0, 0.0]
max = [0.1, {layer}, 0.06]
jitter = 0.1
seed = 1
[[fluid]]
phase = "heavy"
min = [0.0, {layer}, 0.0]
max = [0.1, {top}, 0.06]
jitter = 0.1
seed = 2
[effects.gravity]
[effects.pressure]
{pressure}[effects.viscosity]
)",
                     fmt::arg("end", tomlReal(endTime)), fmt::arg("s", tomlReal(spacing)),
                     fmt::arg("formulation", densityFormulation), fmt::arg("layer", tomlReal(kLayer)),
                     fmt::arg("pressure", pressure), fmt::arg("top", tomlReal(2 * kLayer)));
}

WrongSide massOnTheWrongSide(const ParticleSet& ps, int heavy, double spacing) {
  std::vector<double> y(ps.size());
  size_t nHeavy = 0;
  WrongSide w;
  for (size_t i = 0; i < ps.size(); ++i) {
    y[i] = ps.position[i].y;
    nHeavy += ps.phase[i] == heavy;
    (ps.phase[i] == heavy ? w.heavyMass : w.lightMass) += ps.mass[i];
  }
  if (nHeavy == 0 || nHeavy == y.size()) return w;
  std::sort(y.begin(), y.end());
  const double level = 0.5 * (y[nHeavy - 1] + y[nHeavy]);
  for (size_t i = 0; i < ps.size(); ++i) {
    const double yi = ps.position[i].y;
    if (ps.phase[i] == heavy && yi > level + 0.5 * spacing) w.heavy += ps.mass[i];
    if (ps.phase[i] != heavy && yi < level - 0.5 * spacing) w.light += ps.mass[i];
  }
  return w;
}

std::string closedBoxScene(bool still, double scale, double spacing, double endTime) {
  const double L = scale;
  const std::string block =
      still ? fmt::format("min = [0.0, 0.0, 0.0]\nmax = [{w}, {w}, {w}]\n", fmt::arg("w", tomlReal(0.1 * L)))
            : fmt::format("min = [0.0, {b0}, 0.0]\nmax = [{w}, {b1}, {w}]\nvelocity = [0.0, {v}, 0.0]\n",
                          fmt::arg("w", tomlReal(0.1 * L)), fmt::arg("b0", tomlReal(0.05 * L)),
                          fmt::arg("b1", tomlReal(0.15 * L)), fmt::arg("v", tomlReal(-2.0 * std::sqrt(scale))));
  return fmt::format(R"(
[scene]
name = "{name}"
end_time = {end}
domain_min = [{lo}, {lo}, {lo}]
domain_max = [{hx}, {hy}, {hx}]
[solver]
pressure = "wcsph"
particle_spacing = {s}
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.1
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [{w}, {h}, {w}]
[[fluid]]
phase = "water"
{block}[effects.gravity]
[effects.pressure]
[effects.viscosity]
)",
                     fmt::arg("name", still ? "still_box" : "drop"), fmt::arg("end", tomlReal(endTime * std::sqrt(scale))),
                     fmt::arg("lo", tomlReal(-0.01 * L)), fmt::arg("hx", tomlReal(0.11 * L)),
                     fmt::arg("hy", tomlReal(0.21 * L)), fmt::arg("s", tomlReal(spacing)), fmt::arg("w", tomlReal(0.1 * L)),
                     fmt::arg("h", tomlReal(0.2 * L)), fmt::arg("block", block));
}

Vec3 gravityOf(const Scene& s) {
  const EffectSpec* g = s.effect("gravity");
  return g ? g->vector("acceleration") : Vec3{};
}

double potentialDatumOf(const Scene& s) {
  double y = std::numeric_limits<double>::max();
  for (const auto& solid : s.solids) y = std::min(y, solid.shape == SolidSpec::Shape::Box ? solid.min.y : solid.base.y);
  return s.solids.empty() ? 0 : y;
}

double mechanicalEnergy(const Simulation& sim) {
  const ParticleSet& ps = sim.particles();
  const Scene& scene = sim.scene();
  const Vec3 g = gravityOf(scene);
  const double datumY = potentialDatumOf(scene);
  const bool clamp = scene.solver.clampNegativePressure;
  const double M = sim.gradientMoment();
  double e = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const double m = ps.mass[i];
    e += 0.5 * m * lengthSquared(ps.velocity[i]);
    e -= m * (g.x * ps.position[i].x + g.y * (ps.position[i].y - datumY) + g.z * ps.position[i].z);
    const double r = ps.density[i] / ps.restDensity[i];
    if (r > 1 || !clamp) e += m * ps.stiffness[i] * (std::log(r) + 1 / r - 1) / M;
  }
  return e;
}

}  // namespace mf
