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
#include <limits>
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

  Real band = 0;  // m: half-width of the bend at the level, h / 2 (one spacing by default)

  bool active() const { return weight > 0; }

  /// p_ref / weight at `depth` below the level, and its slope (the body force's share of the
  /// weight): the depth itself below level - band, 0 above level + band, and across the band the
  /// parabola (depth + band)^2 / (4 band) that joins the two with a continuous slope. Why not a
  /// kink at the level: the body force takes the slope exactly, so a kink is a step in it, which
  /// the pair sums (smoothed over the kernel) meet only for the fluid the solve balances; a
  /// particle of another density there is held at the level (water drops parked inside
  /// water_oil's oil). A bend as wide as the kernel's radius is the narrowest it resolves; a wider
  /// one takes lift from a surface layer at the level (docs/method.md, the bend at the level).
  struct Profile {
    Real head = 0, slope = 0;
  };
  Profile profile(Real depth) const {
    if (depth >= band) return {depth, 1};
    if (depth <= -band) return {};
    const Real t = depth + band;
    return {t * t / (4 * band), t / (2 * band)};
  }

  /// How far below the level x lies: negative above it, -infinity outside the containers.
  Real depth(const Vec3& x) const {
    const Real height = dot(x, up);
    if (followsContent) {
      for (size_t c = 0; c < containers.size(); ++c)
        if (insideFluidRegion(containers[c], x)) return levels[c] - height;
      return -std::numeric_limits<Real>::infinity();
    }
    const Real d = level - height;
    if (d <= -band || containers.empty()) return d;  // above the level and its bend, no container walk
    for (const SolidSpec& s : containers)
      if (insideFluidRegion(s, x)) return d;
    return -std::numeric_limits<Real>::infinity();
  }

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
