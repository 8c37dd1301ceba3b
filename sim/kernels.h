// SPH smoothing kernels of Mueller, Charypar & Gross 2003 ("Particle-based fluid simulation
// for interactive applications"), as used by Mueller et al. 2005. h is the support radius:
// every kernel is zero for r >= h.
//  - poly6 for density (eq. 1 of the 2005 paper): smooth, cheap (needs only r^2);
//  - spiky gradient for pressure (eq. 5): does not vanish at r -> 0, so close particles repel;
//  - viscosity-kernel Laplacian for viscosity (eq. 9): positive everywhere, so viscosity
//    only removes relative kinetic energy.
// Each is normalised so that the integral of W over its support is 1 (tested).
#pragma once

#include "vec3.h"

namespace mf {

constexpr Real kPi = 3.14159265358979323846;

struct SphKernels {
  Real h = 0, h2 = 0;
  Real poly6Coef = 0;        // 315 / (64 pi h^9)
  Real spikyCoef = 0;        // 15 / (pi h^6): W_spiky = c (h - r)^3
  Real spikyGradCoef = 0;    // -45 / (pi h^6)
  Real viscLapCoef = 0;      // 45 / (pi h^6)

  SphKernels() = default;
  explicit SphKernels(Real supportRadius) {
    h = supportRadius;
    h2 = h * h;
    const Real h3 = h2 * h, h6 = h3 * h3, h9 = h6 * h3;
    poly6Coef = 315.0 / (64.0 * kPi * h9);
    spikyCoef = 15.0 / (kPi * h6);
    spikyGradCoef = -45.0 / (kPi * h6);
    viscLapCoef = 45.0 / (kPi * h6);
  }

  /// W_poly6(r) from r^2; r2 must be < h2 (callers filter by r2 < h2 first).
  Real poly6(Real r2) const {
    const Real d = h2 - r2;
    return poly6Coef * d * d * d;
  }
  Real poly6Checked(Real r2) const { return r2 < h2 ? poly6(r2) : 0; }

  /// W_spiky(r), only used for tests and diagnostics (pressure uses its gradient).
  Real spiky(Real r) const { return r < h ? spikyCoef * (h - r) * (h - r) * (h - r) : 0; }

  /// grad W_spiky at rij = xi - xj with |rij| = r (0 < r < h). Points from j to i scaled
  /// negative, i.e. grad_i W = -45/(pi h^6) (h-r)^2 rij/r.
  Vec3 spikyGrad(const Vec3& rij, Real r) const {
    if (r <= 0 || r >= h) return {};
    const Real d = h - r;
    return rij * (spikyGradCoef * d * d / r);
  }

  /// Laplacian of the viscosity kernel, 45/(pi h^6) (h - r) for r < h.
  Real viscosityLaplacian(Real r) const { return r < h ? viscLapCoef * (h - r) : 0; }

  /// The viscosity kernel itself (Mueller 2003, eq. 22); only for tests.
  Real viscosityKernel(Real r) const {
    if (r <= 0 || r >= h) return 0;
    const Real q = r / h;
    return 15.0 / (2.0 * kPi * h * h2) * (-0.5 * q * q * q + q * q + 0.5 / q - 1.0);
  }
};

}  // namespace mf
