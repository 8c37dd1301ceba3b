// The pressure's hydrostatic reference (effects.pressure.reference_density, reference_level,
// follow_content): p_ref = rho_ref |g| (level - height along -g) below the level, 0 above. Both
// pressure solvers take it out of the pair and wall sums and apply its exact gradient,
// rho_ref |g| upward per unit volume, as a body force (effects/pressure.cpp for WCSPH,
// pressure/dfsph.cpp for DFSPH).
// The column it describes is the liquid's in its container: in a scene with containers it
// covers the particles inside one, and a particle outside them (boiling's flames under the
// glass) keeps p >= 0 and gets no lift. With follow_content each container has its own level,
// recomputed every step from what the container holds (follow()): for a glass that fills or
// empties, where one fixed level would hold the free surface up at it or leave the liquid's
// lower part uncovered.
#pragma once

#include <algorithm>
#include <vector>

#include "sim/scene.h"
#include "sim/solids.h"

namespace mf {

struct ParticleSet;

struct HydrostaticReference {
  Real weight = 0;   // rho_ref |g|, Pa/m; 0: no reference
  Real density = 0;  // rho_ref, kg/m^3
  Real level = 0;    // m, along up
  Vec3 up;           // -g / |g|
  std::vector<SolidSpec> containers;  // the scene's solids; empty: the reference covers everything
  bool followsContent = false;        // levels[c] from the content of container c (follow())
  std::vector<Real> levels;

  bool active() const { return weight > 0; }
  /// How far below the level x lies: negative above it, and outside the containers.
  Real depth(const Vec3& x) const {
    const Real height = dot(x, up);
    if (followsContent) {
      for (size_t c = 0; c < containers.size(); ++c)
        if (insideFluidRegion(containers[c], x)) return levels[c] - height;
      return -1;
    }
    const Real d = level - height;
    if (d <= 0 || containers.empty()) return d;  // above the level, no container walk
    for (const SolidSpec& s : containers)
      if (insideFluidRegion(s, x)) return d;
    return -1;
  }
  Real pressure(const Vec3& x) const { return weight * std::max(Real(0), depth(x)); }

  /// With followsContent: each container's level is where a column of the reference liquid
  /// would weigh what the container holds (its particles up to its rim, every fluid counted by
  /// its mass), less one particle spacing, so that the settled surface layer is never below it.
  /// Sums run in index order: the same bits on any thread count, and nothing to checkpoint.
  void follow(const ParticleSet& ps, Real spacing);

  /// From the scene's [effects.pressure] table and its gravity; none without either.
  static HydrostaticReference of(const EffectSpec& pressure, const Scene& scene);
};

/// The height (along +y) up to which a container's fluid region holds `volume` (m^3), capped at
/// its top: a box's or a cylinder's constant cross-section, a revolution profile's frusta.
Real heightHolding(const SolidSpec& container, Real volume);

}  // namespace mf
