#include "sim/hydrostatic_reference.h"

#include <cmath>

#include "sim/particles.h"

namespace mf {

Real heightHolding(const SolidSpec& s, Real volume) {
  volume = std::max(Real(0), volume);
  switch (s.shape) {
    case SolidSpec::Shape::Box: {
      const Real area = (s.max.x - s.min.x) * (s.max.z - s.min.z);
      return std::min(s.max.y, s.min.y + volume / area);
    }
    case SolidSpec::Shape::Cylinder:
      return std::min(s.base.y + s.height, s.base.y + volume / (kPi * s.radius * s.radius));
    case SolidSpec::Shape::Revolution: {
      // The radius is linear in the height between profile points: each piece is a frustum,
      // V(t) = pi (r0^2 t + r0 a t^2 + a^2 t^3 / 3) over the first t of it, a its slope.
      const auto& pr = s.profile;
      for (size_t k = 0; k + 1 < pr.size(); ++k) {
        const Real dh = pr[k + 1].first - pr[k].first, r0 = pr[k].second;
        const Real a = (pr[k + 1].second - r0) / dh;
        auto below = [&](Real t) { return kPi * (r0 * r0 * t + r0 * a * t * t + a * a * t * t * t / 3); };
        const Real whole = below(dh);
        if (volume > whole) {
          volume -= whole;
          continue;
        }
        Real lo = 0, hi = dh;  // V(t) is increasing: bisection, a fixed number of halvings
        for (int it = 0; it < 60; ++it) {
          const Real mid = 0.5 * (lo + hi);
          (below(mid) < volume ? lo : hi) = mid;
        }
        return s.base.y + pr[k].first + 0.5 * (lo + hi);
      }
      return s.base.y + pr.back().first;
    }
  }
  return 0;
}

void HydrostaticReference::follow(const ParticleSet& ps, Real spacing) {
  if (!followsContent) return;
  levels.assign(containers.size(), 0);
  for (size_t c = 0; c < containers.size(); ++c) {
    const SolidSpec& s = containers[c];
    Real mass = 0;
    for (size_t i = 0; i < ps.size(); ++i)
      if (insideFluidRegion(s, ps.position[i]) && !aboveOpenTop(s, ps.position[i])) mass += ps.mass[i];
    levels[c] = heightHolding(s, mass / density) - spacing;
  }
}

HydrostaticReference HydrostaticReference::of(const EffectSpec& pressure, const Scene& scene) {
  HydrostaticReference r;
  const EffectSpec* gravity = scene.effect("gravity");
  const Vec3 g = gravity ? gravity->vector("acceleration") : Vec3{};
  const Real gn = length(g), rho = pressure.number("reference_density");
  if (rho > 0 && gn > 0) {
    r.weight = rho * gn;
    r.level = pressure.number("reference_level");
    r.up = g * (-1 / gn);
    r.containers = scene.solids;
    r.followsContent = pressure.number("follow_content") > 0.5;
    r.density = rho;
    r.band = 0.5 * scene.solver.smoothingRatio * scene.solver.particleSpacing;  // h / 2
  }
  return r;
}

}  // namespace mf
