// The curvature of a free surface from a weighted least-squares quadric through the surface
// particles near one particle (a height field over the plane normal to its colour gradient).
//
// Why a fit: the divergence of the unit colour gradient, kappa = -div(n/|n|), is biased upwards
// by the particles' disorder, because each n_i is the very sum of kernel gradients the divergence
// is taken against (docs/method.md, "Where it stands against Laplace and Rayleigh"). The heights of
// the neighbouring surface particles carry the same disorder as zero-mean noise, so the fitted
// curvature scatters but is not biased by it.
#pragma once

#include <cstddef>

#include "../vec3.h"

namespace mf::effects {

/// One point of the fit: its offset from the particle, x_j - x_i, and its weight (> 0).
struct SurfacePoint {
  Vec3 offset;
  Real weight;
};

/// The principal curvatures k1 <= k2 at the particle of the surface through `points` (the
/// particle itself included, at offset 0), positive where the surface bends towards `inward`
/// (a unit vector into the liquid), as a drop's does. The full quadric w = a + b.t + t^T C t
/// (six unknowns) where the points span both tangent directions; the isotropic one
/// w = a + b.t + m |t|^2 (k1 = k2) where they span the quadric's terms too poorly; false where
/// neither is determined (under four points, or all on one line). `length` scales the
/// coordinates (the kernel support) so that the conditioning test is scale-free.
struct PrincipalCurvatures {
  bool valid = false;
  Real k1 = 0, k2 = 0;
};
PrincipalCurvatures fitSurfaceCurvatures(const Vec3& inward, const SurfacePoint* points, size_t count, Real length);

}  // namespace mf::effects
