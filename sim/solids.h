// Solids (containers) as analytic shapes: sampled into boundary particles for the SPH forces
// (Akinci et al. 2012), and used as a last-resort position clamp so that no fluid particle can
// end a step inside a wall, however violent the step was.
#pragma once

#include <vector>

#include "effect.h"
#include "scene.h"

namespace mf {

/// Boundary samples of every solid in the scene, spacing ~ `spacing`, placed `offset` outside
/// each container's surface (see wallSampleOffset).
std::vector<Vec3> sampleSolidSurfaces(const std::vector<SolidSpec>& solids, Real spacing, Real offset);

/// How far outside a container's surface its single layer of samples must sit so that fluid
/// on the seeding lattice (first layer half a spacing from the surface) is at rest density.
/// Akinci's volume 1/sum_k W_bk makes one layer act like a slab of fluid about 0.8 h thick
/// centred on the layer; sampled on the surface itself, half of that slab would overlap the
/// fluid, which would then rest about a spacing away from the wall. Solved numerically
/// (bisection) with the discrete lattice sums of the kernel actually used.
Real wallSampleOffset(const SphKernels& kernels, Real particleSpacing, Real boundarySpacing);

/// Akinci volumes Vb = 1 / sum_k W(x_b - x_k) over boundary samples within h.
BoundarySamples makeBoundarySamples(std::vector<Vec3> positions, const SphKernels& kernels,
                                    const Vec3& gridOrigin);

/// True if p lies in the fluid region of the solid (inside a container), grown by `margin`.
bool insideFluidRegion(const SolidSpec& solid, const Vec3& p, Real margin = 0);

/// Moves a particle that has crossed a wall back onto the wall and removes the velocity
/// component into the wall. Returns true if it had to.
bool clampToFluidRegion(const SolidSpec& solid, Vec3& p, Vec3& v);

/// Radius of a revolution profile at height y above its base (linear between points).
Real profileRadius(const SolidSpec& solid, Real y);

}  // namespace mf
