// SPH smoothing kernels. h is the support radius: every kernel is zero for r >= h.
// Mueller, Charypar & Gross 2003, as used by Mueller et al. 2005:
//  - poly6 (eq. 1 of the 2005 paper): colour fields; density in the papers' kernel choice;
//  - spiky gradient for pressure (eq. 5) in the papers' choice;
//  - viscosity-kernel Laplacian for viscosity (eq. 9): positive everywhere, so viscosity
//    only removes relative kinetic energy.
// Wendland C2 (Wendland 1995; Dehnen & Aly 2012): density and, through its own gradient,
// pressure, by default. A pressure force that is the gradient of the density kernel is the
// gradient of the elastic energy of that density, so a closed box cannot gain energy; the
// papers' spiky gradient on poly6 densities is not, and pumps energy into still water (a box
// of it reached 6 m/s within 1 s). poly6's own gradient would be conservative but vanishes so
// fast at r -> 0 that compressed particles collapse into pairs (median nearest neighbour 0.06
// spacings in still water); Wendland C2's gradient peaks at h/4, well inside the nearest
// neighbour, so pairs repel (Dehnen & Aly: no pairing at any neighbour count). Measured in
// tests/test_physics.cpp (ClosedBox*).
// Each W is normalised so that the integral of W over its support is 1 (tested).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "vec3.h"

namespace mf {

constexpr Real kPi = 3.14159265358979323846;

/// Which kernels measure density and push with pressure (scene key solver.kernel).
enum class KernelChoice {
  WendlandC2,  // density W_wendland, pressure grad W_wendland (conservative; default)
  Muller2003,  // density poly6, pressure grad W_spiky (the papers' choice)
};

struct SphKernels {
  Real h = 0, h2 = 0;
  KernelChoice choice = KernelChoice::WendlandC2;
  Real poly6Coef = 0;        // 315 / (64 pi h^9)
  Real spikyCoef = 0;        // 15 / (pi h^6): W_spiky = c (h - r)^3
  Real spikyGradCoef = 0;    // -45 / (pi h^6)
  Real viscLapCoef = 0;      // 45 / (pi h^6)
  Real wendlandCoef = 0;     // 21 / (2 pi h^3): W = c (1 - q)^4 (1 + 4 q), q = r / h
  Real wendlandGradCoef = 0; // -20 c / h^2: grad W = c' (1 - q)^3 rij

  Real selfWeight = 0;       // a particle's weight in its own density sum (see below)

  SphKernels() = default;
  /// `spacing`, the particles' mean spacing, sets Wendland C2's self-contribution correction;
  /// 0 leaves it out.
  explicit SphKernels(Real supportRadius, KernelChoice kernelChoice = KernelChoice::WendlandC2, Real spacing = 0) {
    h = supportRadius;
    choice = kernelChoice;
    h2 = h * h;
    const Real h3 = h2 * h, h6 = h3 * h3, h9 = h6 * h3;
    poly6Coef = 315.0 / (64.0 * kPi * h9);
    spikyCoef = 15.0 / (kPi * h6);
    spikyGradCoef = -45.0 / (kPi * h6);
    viscLapCoef = 45.0 / (kPi * h6);
    wendlandCoef = 21.0 / (2.0 * kPi * h3);
    wendlandGradCoef = -20.0 * wendlandCoef / h2;
    selfWeight = density(0);
    if (choice == KernelChoice::WendlandC2 && spacing > 0) {
      // Wendland kernels overestimate density by a part of the self-contribution (3.4 % on the
      // rest lattice at h = 2 spacings); Dehnen & Aly 2012, eq. 18: subtract eps W(0), with
      // eps = 0.0294 (N/100)^-0.977 for C2, N = 4/3 pi (h/spacing)^3 neighbours. A constant, so
      // the pressure force (a gradient) is unchanged. Leaves 0.998 on the lattice at h = 2 s.
      const Real neighbours = 4.0 / 3.0 * kPi * (h / spacing) * (h / spacing) * (h / spacing);
      selfWeight *= 1 - 0.0294 * std::pow(neighbours / 100, -0.977);
    }
  }

  /// The density kernel W(r) from r^2 (r2 < h2 required), and its checked form.
  Real density(Real r2) const { return choice == KernelChoice::WendlandC2 ? wendland(r2) : poly6(r2); }
  Real densityChecked(Real r2) const { return r2 < h2 ? density(r2) : 0; }

  /// The kernel gradient of the pressure force at rij = xi - xj, r2 = |rij|^2 (zero outside
  /// the support): grad W_wendland or grad W_spiky, as chosen.
  Vec3 pressureGrad(const Vec3& rij, Real r2) const {
    if (r2 >= h2) return {};
    return choice == KernelChoice::WendlandC2 ? wendlandGrad(rij, r2) : spikyGrad(rij, std::sqrt(r2));
  }

  /// Scales the pressure gradient (the lattice normalisation of Simulation; a constant factor
  /// keeps a conservative force conservative).
  void scalePressureGradient(Real factor) {
    spikyGradCoef *= factor;
    wendlandGradCoef *= factor;
  }

  /// Wendland C2 W(r) from r^2 (r2 < h2 required).
  Real wendland(Real r2) const {
    const Real q = std::sqrt(r2) / h, a = 1 - q;
    return wendlandCoef * (a * a) * (a * a) * (1 + 4 * q);
  }
  /// grad W_wendland at rij with r2 = |rij|^2 < h2.
  Vec3 wendlandGrad(const Vec3& rij, Real r2) const {
    const Real a = 1 - std::sqrt(r2) / h;
    return rij * (wendlandGradCoef * a * a * a);
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

/// The part of a kernel's support that lies beyond a plane free surface, as a function of what
/// a particle can see of it: zeta = |sum_j V_j (x_j - x_i) W_ij| / (h sum_j V_j W_ij) over the
/// neighbours it has (self included). For a half-space of fluid whose surface lies a distance d
/// from the particle, zeta = M(d) / (1 - g(d)) with g(d) = int_{z > d} W and M(d) =
/// int_{z > d} (z/h) W: both scale with the density, so zeta measures the geometry only, and
/// g(d) is the missing fraction of a full neighbourhood. Tabulated for 0 <= d <= h (a particle
/// at or inside the surface): zeta = 0.208 at d = 0, where g = 1/2, its cap.
struct HalfSpaceMissing {
  std::vector<Real> zeta, missing;  // zeta decreasing, from d = 0 to d = h
  Real scale = 1;                   // lattice calibration (Simulation): the answer is scale * g

  HalfSpaceMissing() = default;
  explicit HalfSpaceMissing(const SphKernels& K, int samples = 512) {
    // A(z) = 2 pi int_z^h W(r) r dr (the kernel integrated over the plane at height z), then
    // g(d) = int_d^h A and M(d) = int_d^h (z/h) A, all by the trapezoid rule on a fine grid.
    const int n = 8 * samples;
    const Real dz = K.h / n;
    std::vector<Real> A(n + 1, 0), g(n + 1, 0), M(n + 1, 0);
    for (int k = n - 1; k >= 0; --k) {
      const Real r0 = k * dz, r1 = r0 + dz;
      A[k] = A[k + 1] + kPi * dz * (K.density(r0 * r0) * r0 + (k + 1 < n ? K.density(r1 * r1) * r1 : 0));
    }
    for (int k = n - 1; k >= 0; --k) {
      g[k] = g[k + 1] + 0.5 * dz * (A[k] + A[k + 1]);
      M[k] = M[k + 1] + 0.5 * dz * (k * dz * A[k] + (k + 1) * dz * A[k + 1]) / K.h;
    }
    const Real half = g[0];  // 1/2 up to the quadrature error; used to normalise
    for (int k = 0; k <= n; k += 8) {
      const Real gk = 0.5 * g[k] / half;
      zeta.push_back(0.5 * M[k] / half / (1 - gk));
      missing.push_back(gk);
    }
  }
  /// The missing fraction for a measured zeta (linear in the table; 1/2 above its top).
  Real operator()(Real z) const { return scale * unscaled(z); }
  Real unscaled(Real z) const {
    if (z >= zeta.front()) return missing.front();
    if (z <= 0) return 0;
    // first entry with zeta[k] <= z (zeta decreases with k)
    const size_t k = size_t(std::lower_bound(zeta.begin(), zeta.end(), z, [](Real a, Real b) { return a > b; }) -
                            zeta.begin());
    const Real t = (z - zeta[k]) / (zeta[k - 1] - zeta[k]);
    return missing[k] + t * (missing[k - 1] - missing[k]);
  }
};

}  // namespace mf
