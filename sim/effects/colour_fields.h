// Colour fields of Mueller et al. 2005 (eq. 3 form, c(x) = sum_j V_j c_j W(x - x_j), poly6)
// used to find free surfaces and trapped air. Internal to the effects that need them: a scene
// that enables none of those effects never computes them.
//   c_p (liquid colour): 1 on liquid particles and on the walls, 0 on gas particles and in
//       empty space. Its gradient is large at any liquid surface and points into the liquid.
//   c_a (all-particle colour): 1 on every particle and on the walls, 0 in empty space. Its
//       gradient is large only at the free surface of the whole particle set (where liquid or
//       gas meets space that no particle represents), not at a liquid-gas interface.
// Walls count as 1 in both, with their Akinci volumes, so that a pool's floor is not a surface.
// Particle volumes are rest volumes m_j / rho0_j rather than eq. 3's m_j / rho_j: with the number
// density formulation m_j / rho_j = 1 / (number density), which grows wherever neighbours are
// missing and so fills in the very surfaces the field is meant to find (a thin stream then looks
// like bulk liquid: measured, the tip of a falling jet passed the enclosure test).
// On a flat face of a half-space the continuous gradient is 315/(256 h) = 1.23/h; thresholds are
// given in units of 1/h.
#pragma once

#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

#include "../effect.h"

namespace mf::effects {

/// grad W_poly6 at rij = xi - xj, r2 = |rij|^2 < h^2: -6 c (h^2 - r^2)^2 rij.
inline Vec3 poly6Gradient(const SphKernels& K, const Vec3& rij, Real r2) {
  const Real d = K.h2 - r2;
  return rij * (-6 * K.poly6Coef * d * d);
}

struct ColourGradients {
  std::vector<Vec3> liquid;  // grad c_p
  std::vector<Vec3> all;     // grad c_a
};

/// Rest volume of particle j, the volume its colour counts with.
inline Real colourVolume(const ParticleSet& ps, size_t j) { return ps.mass[j] / ps.restDensity[j]; }

/// Both gradients for every particle whose phase has want[phase] != 0 (others get zero).
/// isLiquid[phase]: 1 for liquid phases.
inline void computeColourGradients(const StepContext& ctx, const ParticleSet& ps, const std::vector<uint8_t>& isLiquid,
                                   const std::vector<uint8_t>& want, ColourGradients& out) {
  const SphKernels& K = ctx.kernels;
  const NeighborLists& nf = ctx.fluidNeighbors;
  const NeighborLists& nb = ctx.boundaryNeighbors;
  const size_t n = ps.size();
  out.liquid.assign(n, Vec3{});
  out.all.assign(n, Vec3{});
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (!want[ps.phase[i]]) continue;
      const Vec3 xi = ps.position[i];
      Vec3 gl, ga;
      for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
        const uint32_t j = nf.indices[k];
        const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
        const Real r2 = lengthSquared(rij);
        if (r2 >= K.h2) continue;
        const Vec3 g = poly6Gradient(K, rij, r2) * colourVolume(ps, j);  // eq. 3
        ga += g;
        if (isLiquid[ps.phase[j]]) gl += g;
      }
      for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
        const uint32_t b = nb.indices[k];
        const Vec3 rib = ctx.periodic.separation(xi, ctx.boundary.position[b]);
        const Real r2 = lengthSquared(rib);
        if (r2 >= K.h2) continue;
        const Vec3 g = poly6Gradient(K, rib, r2) * ctx.boundary.volume[b];
        ga += g;
        gl += g;
      }
      out.liquid[i] = gl;
      out.all[i] = ga;
    }
  });
}

/// The rule for "this gas particle is at the top of the particle set" (trapped air and vapour
/// leave there): |grad c_a| > threshold / h with the normal, which points into the particles,
/// pointing down (n . up < -cosine: empty space above), and no particles at `probe` h above it
/// either: the particles' colour (rest volumes, walls included) at x + probe h up is below 0.25,
/// a quarter of a full neighbourhood. Gaps inside the liquid (the wake of a fast bubble, where
/// the clamped pressure does not pull water back at once) open below, beside or above gas as
/// often as the open surface does; measured, without the direction test and the probe most of a
/// rising bubble was deleted half way up.
struct OpenSurfaceRule {
  Real threshold = 0.6;  // 1/h
  Real cosine = 0.5;
  Real probe = 1.0;      // h; 0: no probe
  Vec3 up{0, 1, 0};

  bool gradientSaysOpen(const Vec3& gradAll, Real h) const {
    const Real g2 = lengthSquared(gradAll), t = threshold / h;
    return g2 > t * t && dot(gradAll, up) < -cosine * std::sqrt(g2);
  }

  /// Clears flags[i] (set by gradientSaysOpen) where there are particles above particle i.
  void confirmWithProbe(const StepContext& ctx, const ParticleSet& ps, std::vector<uint8_t>& flags, uint8_t value) const {
    std::vector<uint32_t> flagged;
    for (size_t i = 0; i < ps.size(); ++i)
      if (flags[i] == value) flagged.push_back(uint32_t(i));
    if (flagged.empty() || probe <= 0) return;
    const SphKernels& K = ctx.kernels;
    std::vector<Vec3> at(flagged.size());
    for (size_t c = 0; c < flagged.size(); ++c) at[c] = ps.position[flagged[c]] + up * (probe * K.h);
    CellGrid grid;
    grid.build(at.data(), at.size(), ctx.gridOrigin, K.h);
    NeighborLists fluidNb, wallNb;
    grid.findNeighbors(*ctx.fluidGrid, K.h, false, fluidNb, ctx.periodic);
    if (ctx.boundaryGrid) grid.findNeighbors(*ctx.boundaryGrid, K.h, false, wallNb, ctx.periodic);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, flagged.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t c = r.begin(); c != r.end(); ++c) {
        Real fill = 0;
        for (uint64_t k = fluidNb.begin(c), e = fluidNb.end(c); k < e; ++k)
          fill += colourVolume(ps, fluidNb.indices[k]) * K.poly6Checked(lengthSquared(ctx.periodic.separation(at[c], ps.position[fluidNb.indices[k]])));
        if (ctx.boundaryGrid)
          for (uint64_t k = wallNb.begin(c), e = wallNb.end(c); k < e; ++k)
            fill += ctx.boundary.volume[wallNb.indices[k]] *
                    K.poly6Checked(lengthSquared(ctx.periodic.separation(at[c], ctx.boundary.position[wallNb.indices[k]])));
        if (fill >= 0.25) flags[flagged[c]] = 0;
      }
    });
  }
};

}  // namespace mf::effects
