// Kernel properties the solver relies on: unit integral, gradient and Laplacian formulas that
// match the kernels they come from, antisymmetric gradients, and the lattice calibrations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sim/kernels.h"
#include "sim/simulation.h"

namespace {

constexpr double kH = 0.02;

// integral over the ball of W(r) = 4 pi int_0^h W(r) r^2 dr, Simpson's rule with 20000 intervals:
// error far below the tolerance for these polynomial-like kernels.
template <class F>
double radialIntegral(F&& w, double h) {
  const int n = 20000;
  const double dr = h / n;
  double sum = 0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * dr;
    const double c = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    sum += c * w(r) * r * r;
  }
  return 4 * mf::kPi * sum * dr / 3;
}

TEST(Kernels, Poly6SpikyAndWendlandIntegrateToOne) {
  const mf::SphKernels K(kH);
  EXPECT_NEAR(radialIntegral([&](double r) { return K.poly6Checked(r * r); }, kH), 1.0, 1e-9);
  EXPECT_NEAR(radialIntegral([&](double r) { return K.densityChecked(r * r); }, kH), 1.0, 1e-9);  // Wendland C2
  EXPECT_NEAR(radialIntegral([&](double r) { return K.spiky(r); }, kH), 1.0, 1e-9);
  // The viscosity kernel has an integrable r^-1 singularity at 0: Simpson loses accuracy there.
  EXPECT_NEAR(radialIntegral([&](double r) { return K.viscosityKernel(r); }, kH), 1.0, 1e-4);
}

TEST(Kernels, ZeroAtAndBeyondSupport) {
  const mf::SphKernels K(kH);
  EXPECT_EQ(K.poly6Checked(kH * kH), 0.0);
  EXPECT_EQ(K.spiky(kH), 0.0);
  EXPECT_EQ(K.viscosityLaplacian(kH), 0.0);
  EXPECT_EQ(K.spikyGrad({kH * 1.01, 0, 0}, kH * 1.01), mf::Vec3());
  EXPECT_EQ(K.densityChecked(kH * kH), 0.0);
  EXPECT_EQ(K.pressureGrad({kH, 0, 0}, kH * kH), mf::Vec3());
}

TEST(Kernels, WendlandGradientIsDerivativeOfWendlandAndAntisymmetric) {
  const mf::SphKernels K(kH);
  ASSERT_EQ(K.choice, mf::KernelChoice::WendlandC2);
  for (double q : {0.1, 0.35, 0.6, 0.9}) {
    const mf::Vec3 dir = mf::normalize(mf::Vec3(0.3, -0.5, 0.8));
    const double r = q * kH, e = 1e-7 * kH;
    const double fd = (K.density((r + e) * (r + e)) - K.density((r - e) * (r - e))) / (2 * e);  // dW/dr
    const mf::Vec3 g = K.pressureGrad(dir * r, r * r);
    EXPECT_NEAR(mf::dot(g, dir), fd, 1e-6 * std::fabs(fd)) << "q = " << q;
    EXPECT_NEAR(mf::length(mf::cross(g, dir)), 0.0, 1e-9 * std::fabs(fd));
    EXPECT_EQ(K.pressureGrad(-(dir * r), r * r), -g);  // exactly: pair forces must cancel bit for bit
  }
}

TEST(Kernels, SpikyGradientIsDerivativeOfSpikyAndAntisymmetric) {
  const mf::SphKernels K(kH);
  for (double q : {0.1, 0.35, 0.6, 0.9}) {
    const mf::Vec3 dir = mf::normalize(mf::Vec3(0.3, -0.5, 0.8));
    const double r = q * kH, e = 1e-7 * kH;
    const double fd = (K.spiky(r + e) - K.spiky(r - e)) / (2 * e);  // dW/dr
    const mf::Vec3 g = K.spikyGrad(dir * r, r);
    EXPECT_NEAR(mf::dot(g, dir), fd, 1e-6 * std::fabs(fd)) << "q = " << q;
    EXPECT_NEAR(mf::length(mf::cross(g, dir)), 0.0, 1e-9 * std::fabs(fd));
    const mf::Vec3 gm = K.spikyGrad(-(dir * r), r);
    EXPECT_EQ(gm, -g);  // exactly: pair forces must cancel bit for bit
  }
}

TEST(Kernels, ViscosityLaplacianMatchesKernel) {
  // Laplacian of a radial function: W'' + 2 W' / r, by central differences.
  const mf::SphKernels K(kH);
  for (double q : {0.2, 0.5, 0.8}) {
    const double r = q * kH, e = 1e-4 * kH;
    const double w0 = K.viscosityKernel(r), wp = K.viscosityKernel(r + e), wm = K.viscosityKernel(r - e);
    const double lap = (wp - 2 * w0 + wm) / (e * e) + 2 / r * (wp - wm) / (2 * e);
    EXPECT_NEAR(K.viscosityLaplacian(r), lap, 1e-5 * lap) << "q = " << q;
    EXPECT_GT(K.viscosityLaplacian(r), 0.0);
  }
}

TEST(Kernels, LatticeCalibration) {
  // A particle inside a cubic lattice with spacing s = h/2: the lattice kernel sum times s^3
  // approximates the integral (1): poly6 to about 1 %; Wendland C2 overestimates it by 3.4 %
  // (its self-contribution bias), and Dehnen & Aly's correction brings it within 0.5 %. The
  // raw gradient moments are 0.947 (spiky) and 0.950 (Wendland C2; 0.984 with the corrected
  // particle volume), which the solver divides out.
  const double s = kH / 2;
  struct Case {
    mf::KernelChoice choice;
    double spacing, sum, sumTolerance, moment;
  };
  for (const Case& c : {Case{mf::KernelChoice::Muller2003, s, 1.0, 0.015, 0.947},
                        Case{mf::KernelChoice::WendlandC2, 0, 1.034, 0.001, 0.950},
                        Case{mf::KernelChoice::WendlandC2, s, 1.0, 0.005, 0.984}}) {
    mf::SphKernels K(kH, c.choice, c.spacing);
    EXPECT_NEAR(mf::latticeKernelSum(K, s) * s * s * s, c.sum, c.sumTolerance);
    const double m = mf::latticeGradientMoment(K, s);
    EXPECT_NEAR(m, c.moment, 0.002);
    K.scalePressureGradient(1 / m);
    EXPECT_NEAR(mf::latticeGradientMoment(K, s), 1.0, 1e-12);
  }
}

// A particle moved off its lattice site, its neighbours held: its density sum rises, so every
// site is a density minimum. DFSPH's constant-density solve holds each particle's density within
// its tolerance (5e-4 by default), so a well deeper than that holds particles on their sites:
// a tenth of a spacing costs 11.1 tolerances at h = 2 spacings, where a light blob does not rise,
// and 5.9 at 2.25, where it does (docs/pressure_solvers.md). Measured here with
// the solver's own kernel and self weight; bounds about 5 % of each value.
TEST(Kernels, ALatticeSiteIsADensityMinimumWhoseDepthFallsWithTheSupport) {
  const double s = 0.01;
  auto rise = [&](double ratio, mf::Vec3 offset) {
    const mf::SphKernels K(ratio * s, mf::KernelChoice::WendlandC2, s);
    // The density sum at `at` from the lattice's neighbours (the particle itself left out).
    auto neighbours = [&](mf::Vec3 at) {
      return mf::sumOverRestLattice(K, s, [&](int i, int j, int k) {
        return i == 0 && j == 0 && k == 0 ? 0.0 : K.densityChecked(mf::lengthSquared(mf::Vec3(i * s, j * s, k * s) - at));
      });
    };
    return (K.selfWeight + neighbours(offset)) / (K.selfWeight + neighbours(mf::Vec3())) - 1;
  };
  const mf::Vec3 tenth(0.1 * s, 0, 0), half(0.5 * s, 0, 0), diagonal(0.1 * s, 0.1 * s, 0.1 * s);
  const double tolerance = 5e-4;
  for (double ratio : {2.0, 2.25, 2.5}) {
    std::printf("h = %.2f spacings: a tenth of a spacing off the site +%.3f %% (%.1f tolerances), half +%.2f %%\n", ratio,
                100 * rise(ratio, tenth), rise(ratio, tenth) / tolerance, 100 * rise(ratio, half));
    EXPECT_GT(rise(ratio, tenth), 0);
    EXPECT_GT(rise(ratio, diagonal), rise(ratio, tenth));
    EXPECT_GT(rise(ratio, half), rise(ratio, tenth));
  }
  EXPECT_NEAR(rise(2.0, tenth) / tolerance, 11.1, 0.5);
  EXPECT_NEAR(rise(2.25, tenth) / tolerance, 5.9, 0.3);
}

// Eq. 9's viscosity sum, sum_j V_j (v_j - v_i) lap W_ij, applied on the rest lattice to
// v = x^2 / 2, whose Laplacian is 1. Unlike the pressure gradient it is not normalised on the
// lattice: 0.988 at h = 2 spacings (the periodic shear wave decays 1.8 % slow), 0.877 at 2.25
// (11.4 % slow), 1.021 at 2.5. This is what a support of 2.25 would need calibrated first
// (docs/pressure_solvers.md#the-kernel-support-under-dfsph). Bounds 0.002.
TEST(Kernels, TheViscousLaplacianOnTheLatticeDependsOnTheSupport) {
  const double s = 0.01;
  auto laplacian = [&](double ratio) {
    const mf::SphKernels K(ratio * s, mf::KernelChoice::WendlandC2, s);
    return mf::sumOverRestLattice(K, s, [&](int i, int j, int k) {
      const double r = s * std::sqrt(double(i * i + j * j + k * k));
      return r > 0 ? s * s * s * 0.5 * (i * s) * (i * s) * K.viscosityLaplacian(r) : 0.0;
    });
  };
  std::printf("lattice viscous Laplacian of x^2/2 (exact 1): h = 2: %.4f, 2.25: %.4f, 2.5: %.4f\n", laplacian(2.0),
              laplacian(2.25), laplacian(2.5));
  EXPECT_NEAR(laplacian(2.0), 0.988, 0.002);
  EXPECT_NEAR(laplacian(2.25), 0.877, 0.002);
  EXPECT_NEAR(laplacian(2.5), 1.021, 0.002);
}

}  // namespace
