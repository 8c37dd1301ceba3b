// Solids (containers) as analytic shapes: sampled into boundary particles for the SPH forces
// (Akinci et al. 2012), and used as a last-resort position clamp so that no fluid particle can
// end a step inside a wall, however violent the step was.
#pragma once

#include <vector>

#include "effect.h"
#include "scene.h"

namespace mf {

/// Boundary samples of every solid in the scene, spacing ~ `spacing`, placed `offset` outside
/// each container's surface (see wallSampleOffset). On a periodic axis a box spans the period,
/// its faces across that axis are left out and its lattice tiles (n samples per period, the
/// last one the first's image); other solids' samples outside the period are dropped.
std::vector<Vec3> sampleSolidSurfaces(const std::vector<SolidSpec>& solids, Real spacing, Real offset,
                                      const PeriodicDomain& periodic = {});

/// How far outside a container's surface its single layer of samples must sit so that fluid
/// on the seeding lattice (first layer half a spacing from the surface) is at rest density.
/// Akinci's volume 1/sum_k W_bk makes one layer act like a slab of fluid about 0.8 h thick
/// centred on the layer; sampled on the surface itself, half of that slab would overlap the
/// fluid, which would then rest about a spacing away from the wall. Solved numerically
/// (bisection) with the discrete lattice sums of the kernel actually used.
Real wallSampleOffset(const SphKernels& kernels, Real particleSpacing, Real boundarySpacing);

/// The single sample layer of the walls as DFSPH uses it. The wall is one term of a particle's
/// density, theta_i = sum_j V_j W_ij + sum_b V_b W_ib, and its pressure force is -p_i V_i times
/// that term's gradient, so the force stays the adjoint of the constraint it enforces and does
/// no work over a closed path. Two conditions on the seeding lattice fix the layer's depth and a
/// scale on its Akinci volumes: the first fluid layer (half a spacing from the surface) is at
/// rest density, and a uniform pressure pushes it off the wall as hard as the missing
/// half-lattice would push it on (twice sum_j V_j grad W_ij over that half: the pair force
/// counts p_i + p_j). A wall weighted more in the force than in the density (a "mirror factor",
/// 1.7 here before) fed energy into a closed still tank; see docs/pressure_solvers.md#walls.
struct WallCalibration {
  Real offset = 0;         // depth of the sample layer below the surface, m
  Real volumeScale = 1;    // on V_b = 1 / sum_k W_bk
  Real contactHeight = 0;  // a lone particle reads rest density this far above the surface, m
};
WallCalibration calibrateImplicitWall(const SphKernels& kernels, Real particleSpacing, Real boundarySpacing);

/// Akinci volumes Vb = 1 / sum_k W(x_b - x_k) over boundary samples within h.
BoundarySamples makeBoundarySamples(std::vector<Vec3> positions, const SphKernels& kernels,
                                    const Vec3& gridOrigin, Real volumeScale = 1,
                                    const PeriodicDomain& periodic = {});

/// True if p lies in the fluid region of the solid (inside a container), grown by `margin`.
bool insideFluidRegion(const SolidSpec& solid, const Vec3& p, Real margin = 0);

/// True if p is above the rim of an open-top container: out of it, over no wall.
bool aboveOpenTop(const SolidSpec& solid, const Vec3& p);

/// Moves a particle that has crossed a wall back onto the wall and removes the velocity
/// component into the wall. Returns true if it had to.
bool clampToFluidRegion(const SolidSpec& solid, Vec3& p, Vec3& v);

/// Radius of a revolution profile at height y above its base (linear between points).
Real profileRadius(const SolidSpec& solid, Real y);

}  // namespace mf
