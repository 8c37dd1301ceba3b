// The pressure's hydrostatic reference (effects.pressure.reference_density, reference_level):
// p_ref = rho_ref |g| (level - height along -g) below the level, 0 above. Both pressure solvers
// take it out of the pair and wall sums and apply its exact gradient, rho_ref |g| upward per unit
// volume, as a body force (effects/pressure.cpp for WCSPH, pressure/dfsph.cpp for DFSPH).
// The column it describes is the liquid's in its container: in a scene with containers it
// covers the particles inside one, and a particle outside them (boiling's flames under the
// glass) keeps p >= 0 and gets no lift.
#pragma once

#include <algorithm>
#include <vector>

#include "sim/scene.h"
#include "sim/solids.h"

namespace mf {

struct HydrostaticReference {
  Real weight = 0;  // rho_ref |g|, Pa/m; 0: no reference
  Real level = 0;   // m, along up
  Vec3 up;          // -g / |g|
  std::vector<SolidSpec> containers;  // the scene's solids; empty: the reference covers everything

  bool active() const { return weight > 0; }
  /// How far below the level x lies: negative above it, and outside the containers.
  Real depth(const Vec3& x) const {
    const Real d = level - dot(x, up);
    if (d <= 0 || containers.empty()) return d;
    for (const SolidSpec& s : containers)
      if (insideFluidRegion(s, x)) return d;
    return -1;
  }
  Real pressure(const Vec3& x) const { return weight * std::max(Real(0), depth(x)); }

  /// From the scene's [effects.pressure] table and its gravity; none without either.
  static HydrostaticReference of(const EffectSpec& pressure, const Scene& scene) {
    HydrostaticReference r;
    const EffectSpec* gravity = scene.effect("gravity");
    const Vec3 g = gravity ? gravity->vector("acceleration") : Vec3{};
    const Real gn = length(g), rho = pressure.number("reference_density");
    if (rho > 0 && gn > 0) r = {rho * gn, pressure.number("reference_level"), g * (-1 / gn), scene.solids};
    return r;
  }
};

}  // namespace mf
