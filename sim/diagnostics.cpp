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

std::string freeDropScene(const std::string& solver, double R, double spacing, double sigma, double endTime) {
  return fmt::format(R"([scene]
name = "drop"
end_time = {end}
domain_min = [-0.5, -0.5, -0.5]
domain_max = [0.5, 0.5, 0.5]
[solver]
particle_spacing = {s}
max_dt = 0.005
pressure = "{solver}"
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 100.0
viscosity = 0.01
surface_tension = {sigma}
[[fluid]]
phase = "water"
shape = "sphere"
centre = [0.0, 0.0, 0.0]
radius = {R}
[effects.pressure]
[effects.viscosity]
[effects.surface_tension]
)",
                     fmt::arg("end", tomlReal(endTime)), fmt::arg("s", tomlReal(spacing)), fmt::arg("solver", solver),
                     fmt::arg("sigma", tomlReal(sigma)), fmt::arg("R", tomlReal(R)));
}

std::string bubbleInTankScene(double gasDensity, double addedDensity, double R) {
  return fmt::format(R"([scene]
name = "bubble"
end_time = 0.01
frame_rate = 100
domain_min = [-0.05, -0.05, -0.05]
domain_max = [0.25, 0.45, 0.25]
[solver]
pressure = "dfsph"
particle_spacing = 0.01
max_dt = 0.0005
density_formulation = "number"
[[phase]]
name = "water"
rest_density = 1000.0
[[phase]]
name = "air"
rest_density = {rho}
added_density = {added}
[[solid]]
name = "tank"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.4, 0.2]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.2, 0.3, 0.2]
[[fluid.subtract]]
shape = "sphere"
centre = [0.105, 0.105, 0.105]
radius = {R}
[[fluid]]
phase = "air"
shape = "sphere"
centre = [0.105, 0.105, 0.105]
radius = {R}
[effects.gravity]
)",
                     fmt::arg("rho", tomlReal(gasDensity)), fmt::arg("added", tomlReal(addedDensity)), fmt::arg("R", tomlReal(R)));
}

double volumeRadius(size_t n, double spacing) { return std::cbrt(3 * double(n) * std::pow(spacing, 3) / (4 * kPi)); }

Vec3 centroidOf(const ParticleSet& q, const std::function<bool(size_t)>& in) {
  Vec3 c;
  size_t n = 0;
  for (size_t i = 0; i < q.size(); ++i)
    if (!in || in(i)) c += q.position[i], ++n;
  return n ? c * (1.0 / double(n)) : c;
}

double meanPressureNearCentroid(const ParticleSet& q, double radius) {
  const Vec3 c = centroidOf(q);
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < q.size(); ++i)
    if (length(q.position[i] - c) < radius) sum += q.mechanicalPressure(i), ++count;
  return count ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

double quadrupoleMoment(const ParticleSet& q, const std::function<bool(size_t)>& inDrop) {
  const Vec3 c = centroidOf(q, inDrop);
  double m = 0;
  for (size_t i = 0; i < q.size(); ++i)
    if (inDrop(i)) {
      const Vec3 d = q.position[i] - c;
      m += d.x * d.x - 0.5 * (d.y * d.y + d.z * d.z);
    }
  return m;
}

void kickQuadrupoleMode(ParticleSet& q, const std::function<bool(size_t)>& inDrop, const Vec3& centre, double R, double omega,
                        double amplitude) {
  const double A = amplitude * omega / 2, C = -2 * A * std::pow(R, 5) / 3;
  for (size_t i = 0; i < q.size(); ++i) {
    const Vec3 d = q.position[i] - centre;
    if (inDrop(i)) {
      q.velocity[i] = Vec3(2 * A * d.x, -A * d.y, -A * d.z);
      continue;
    }
    // grad (f / r^5) = grad f / r^5 - 5 f d / r^7, f = (3 x^2 - r^2) / 2
    const double r2 = lengthSquared(d), r5 = r2 * r2 * std::sqrt(r2), f = 0.5 * (3 * d.x * d.x - r2);
    q.velocity[i] = (Vec3(2 * d.x, -d.y, -d.z) * (1 / r5) - d * (5 * f / (r5 * r2))) * C;
  }
}

double kickedQuadrupole(size_t n, double R, double amplitude) { return double(n) * R * R * 3 * amplitude / 5; }

Oscillation oscillationOf(const std::vector<double>& t, const std::vector<double>& q, double window) {
  Oscillation o;
  if (t.empty()) return o;
  std::vector<double> maxima, minima;
  for (size_t k = 0; k < t.size(); ++k) {
    if (t[k] < t.front() + window || t[k] > t.back() - window) continue;
    bool isMax = true, isMin = true;
    for (size_t j = 0; j < t.size(); ++j)
      if (std::fabs(t[j] - t[k]) <= window) isMax = isMax && q[j] <= q[k], isMin = isMin && q[j] >= q[k];
    if (isMax) maxima.push_back(t[k]);
    if (isMin) minima.push_back(t[k]);
    o.largest = std::max(o.largest, std::fabs(q[k]));
  }
  o.maxima = maxima.size(), o.minima = minima.size();
  const size_t spans = (maxima.size() > 1 ? maxima.size() - 1 : 0) + (minima.size() > 1 ? minima.size() - 1 : 0);
  if (spans == 0) return o;
  double sum = 0;
  for (size_t k = 1; k < maxima.size(); ++k) sum += maxima[k] - maxima[k - 1];
  for (size_t k = 1; k < minima.size(); ++k) sum += minima[k] - minima[k - 1];
  o.period = sum / double(spans);
  return o;
}

KickOutcome kickOutcome(const Oscillation& o, size_t seeded, size_t kept, double kicked) {
  if (100 * (seeded - kept) > seeded || o.largest > 3 * kicked) return KickOutcome::CameApart;
  if (std::isnan(o.period) || o.largest < 0.25 * kicked) return KickOutcome::DiedOut;
  return KickOutcome::Period;
}

}  // namespace mf
