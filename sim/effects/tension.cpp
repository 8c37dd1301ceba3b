// Interface and surface tension from colour fields, Mueller et al. 2005, section 4.1.
// A colour field c is smoothed with SPH (eq. 1 form): c(x) = sum_j V_j c_j W(x - x_j); its
// gradient n = grad c is the interface normal (scaled by the jump), its Laplacian carries the
// curvature. The force density is f = -sigma lap(c) n/|n| (eqs. 3, 4; CSF, Brackbill 1992),
// applied only where |n| is above a threshold so that the bulk, where n is noise, stays quiet.
// The force on particle i is V_i f_i. Kernel: poly6 (Mueller et al. 2003, section 3.5).
//
//  - interface_tension: c_i per fluid (water -0.5, oil +0.5). Three models (scene key `model`):
//    2 (default) the capillary stress of Hu & Adams (2006), momentum-conserving; 1 CSF with the
//    curvature -div(n/|n|); 0 the paper's -sigma lap(c) n/|n| as written. Measured on a random
//    50/50 mixture (tests/test_interaction.cpp): 0 collapses unlike pairs within 0.7 s (poly6's
//    Laplacian changes sign at 0.65 h, so close unlike neighbours attract); 1 is stable but
//    barely sorts particle-scale noise (1 % fewer unlike contacts in 1.5 s); 2 sorts it.
//    The gradient is written in difference form,
//    sum_j V_j (c_j - c_i) ..., so only unlike neighbours contribute: it acts at fluid-fluid
//    interfaces and never at a free surface (that is surface_tension's job). sigma_i is given
//    per pair of fluids; a particle uses the pair values of its unlike neighbours, weighted by W.
//  - surface_tension: c_s = 1 for liquids, 0 for gases. Plain sum, because at a free surface
//    without gas particles the missing neighbours are the signal. Walls count as colour
//    `wall_colour` (1: a wall looks like liquid, no pull along it). The lattice residual of the
//    Laplacian sum is subtracted so that a uniform neighbourhood gives exactly zero. On DFSPH
//    the curvature is fitted to the surface particles instead (surface_fit.h): the divergence
//    of the noisy normals reads a free drop's curvature 1.2-1.9 times too high.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "../simulation.h"
#include "builtin.h"
#include "surface_fit.h"

namespace mf::effects {

namespace {

struct Poly6Derivatives {
  Real gradCoef = 0;  // grad W = gradCoef (h^2 - r^2)^2 r_ij
  Real lapCoef = 0;   // lap W = lapCoef (h^2 - r^2) (3 h^2 - 7 r^2)
  Real h2 = 0;
  explicit Poly6Derivatives(const SphKernels& K) : gradCoef(-6 * K.poly6Coef), lapCoef(-6 * K.poly6Coef), h2(K.h2) {}
  Vec3 grad(const Vec3& rij, Real r2) const {
    const Real d = h2 - r2;
    return rij * (gradCoef * d * d);
  }
  Real lap(Real r2) const { return lapCoef * (h2 - r2) * (3 * h2 - 7 * r2); }
};

}  // namespace

/// 1 / M, M = sum_j V (x_j - x_i)_x (grad W_ij)_x over the rest lattice (V = 1 / the lattice's
/// kernel sum, the volume a particle has there): the SPH gradient of a linear field is M times
/// the true one. M is 1 for the continuous integral but 1.067 for poly6 on the lattice at h = 2
/// spacings, and the capillary stress takes the gradient twice (the colour's, then the stress's
/// divergence), so without the factor the tension is 1.14 sigma.
Real colourGradientScale(const SphKernels& K, Real s) {
  const Poly6Derivatives D(K);
  const Real V = 1.0 / latticeKernelSum(K, s);
  const Real M = sumOverRestLattice(K, s, [&](int a, int b, int c) {
    const Real r2 = s * s * Real(a * a + b * b + c * c);
    if (r2 >= K.h2) return 0.0;
    return V * (a * s) * D.grad(Vec3(-a * s, -b * s, -c * s), r2).x;  // c_j - c_i = (x_j - x_i)_x, r_ij = x_i - x_j
  });
  return 1.0 / M;
}

namespace {

/// Brackbill's capillary limit dt <= sqrt(rho dx^3 / (2 pi sigma)) for the smallest rest density.
Real capillaryTimeStep(const Scene& scene, Real sigmaMax) {
  if (sigmaMax <= 0) return std::numeric_limits<Real>::infinity();
  Real rhoMin = 1e300;
  for (const PhaseSpec& p : scene.phases) rhoMin = std::min(rhoMin, p.restDensity);
  const Real dx = scene.solver.particleSpacing;
  return std::sqrt(rhoMin * dx * dx * dx / (2 * kPi * sigmaMax));
}

/// Adds V_i f_i where |n_i| > minNormal. With the paper's form f = -sigma lap(c) n/|n| (eq. 4)
/// when !curvatureFromNormals; otherwise f = sigma kappa n with kappa = -div(n/|n|) (Morris 2000),
/// the divergence taken over neighbours with reliable normals and renormalised by the same
/// partial sum for a linear field, sum_j V_j (x_j - x_i) . grad W_ij = 3 in full support.
/// Why the second form: lap(c) changes sign across the smoothed surface, so a particle that
/// sticks out of a free surface (low c, lap c > 0) is pushed further out and flies off; the
/// divergence of the unit normal is the curvature itself and pulls it back.
void applyTensionForce(const StepContext& ctx, ParticleSet& ps, const std::vector<Vec3>& normal,
                       const std::vector<Real>& lap, const std::vector<Real>& sigma, Real minNormal,
                       bool curvatureFromNormals) {
  const Poly6Derivatives D(ctx.kernels);
  const SphKernels& K = ctx.kernels;
  const NeighborLists& nf = ctx.fluidNeighbors;
  const Real minNormal2 = minNormal * minNormal;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 512), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Real nl2 = lengthSquared(normal[i]);
      if (sigma[i] == 0 || nl2 <= minNormal2) continue;
      const Real nl = std::sqrt(nl2);
      if (!curvatureFromNormals) {
        ps.force[i] += normal[i] * (-sigma[i] * lap[i] * ps.volume[i] / nl);
        continue;
      }
      const Vec3 ni = normal[i] / nl, xi = ps.position[i];
      Real div = 0, linear = 0;
      for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
        const uint32_t j = nf.indices[k];
        const Real nj2 = lengthSquared(normal[j]);
        if (nj2 <= minNormal2) continue;
        const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
        const Real r2 = lengthSquared(rij);
        if (r2 >= K.h2) continue;
        const Vec3 g = D.grad(rij, r2) * ps.volume[j];
        div += dot(normal[j] / std::sqrt(nj2) - ni, g);
        linear -= dot(rij, g);
      }
      if (linear <= 0) continue;
      const Real kappa = -3 * div / linear;
      ps.force[i] += normal[i] * (sigma[i] * kappa * ps.volume[i]);
    }
  });
}

class InterfaceTension final : public Effect {
 public:
  enum class Model { Laplacian = 0, Curvature = 1, Stress = 2 };
  InterfaceTension(std::vector<Real> sigma, size_t phaseCount, Real threshold, Model model, Real spacing, Real dtLimit)
      : sigma_(std::move(sigma)),
        phaseCount_(phaseCount),
        threshold_(threshold),
        model_(model),
        spacing_(spacing),
        dtLimit_(dtLimit) {}
  const char* name() const override { return "interface_tension"; }
  AttributeMask requiredAttributes() const override { return bit(Attribute::InterfaceColour); }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const Poly6Derivatives D(ctx.kernels);
    const SphKernels& K = ctx.kernels;
    if (scaleH_ != K.h) gradScale_ = colourGradientScale(K, spacing_), scaleH_ = K.h;
    const NeighborLists& nf = ctx.fluidNeighbors;
    const size_t n = ps.size();
    normal_.resize(n);
    lap_.resize(n);
    sigma_i_.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Vec3 xi = ps.position[i];
        const Real ci = ps.interfaceColour[i];
        const size_t rowI = size_t(ps.phase[i]) * phaseCount_;
        Vec3 grad;
        Real lap = 0, sigmaW = 0, sumW = 0;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Real dc = ps.interfaceColour[j] - ci;
          if (dc == 0) continue;  // like neighbours contribute nothing in difference form
          const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
          const Real r2 = lengthSquared(rij);
          if (r2 >= K.h2) continue;
          const Real Vdc = ps.volume[j] * dc;
          grad += D.grad(rij, r2) * Vdc;  // eq. 3
          lap += Vdc * D.lap(r2);         // eq. 4 (model 0 only)
          const Real w = K.poly6(r2);
          sigmaW += sigma_[rowI + ps.phase[j]] * w;
          sumW += w;
        }
        normal_[i] = grad * gradScale_;
        lap_[i] = lap;
        sigma_i_[i] = sumW > 0 ? sigmaW / sumW : 0;
      }
    });
    if (model_ == Model::Stress) applyStressForce(ctx, ps, threshold_ / K.h);
    else applyTensionForce(ctx, ps, normal_, lap_, sigma_i_, threshold_ / K.h, model_ == Model::Curvature);
  }

  Real maxTimeStep(const StepContext&, const ParticleSet&) const override { return dtLimit_; }

 private:
  /// Hu & Adams (2006): the capillary stress Pi = sigma/|n| (|n|^2 I/3 - n n^T) (traceless), its
  /// divergence in the same pair form as the pressure force, F_i = sum_j V_i V_j (Pi_i + Pi_j) grad W_ij.
  /// Antisymmetric, so momentum is conserved; its divergence is the CSF force sigma kappa n plus
  /// a pressure-like term. Where |n| is below the threshold Pi is zero.
  void applyStressForce(const StepContext& ctx, ParticleSet& ps, Real minNormal) {
    const size_t n = ps.size();
    stress_.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Vec3 g = normal_[i];
        const Real gl = length(g);
        Sym& S = stress_[i];
        if (gl <= minNormal || sigma_i_[i] == 0) {
          S = Sym{};
          continue;
        }
        const Real a = sigma_i_[i] / gl, iso = gl * gl / 3;
        S = {a * (iso - g.x * g.x), a * (iso - g.y * g.y), a * (iso - g.z * g.z), -a * g.x * g.y, -a * g.x * g.z, -a * g.y * g.z};
      }
    });
    const SphKernels& K = ctx.kernels;
    const Poly6Derivatives D(K);
    const NeighborLists& nf = ctx.fluidNeighbors;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Sym& Si = stress_[i];
        const bool activeI = !Si.zero();
        const Vec3 xi = ps.position[i];
        Vec3 f;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Sym& Sj = stress_[j];
          if (!activeI && Sj.zero()) continue;
          const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
          const Real r2 = lengthSquared(rij);
          if (r2 >= K.h2) continue;
          // poly6's gradient vanishes at r -> 0, so the tangential tension has no grip on a
          // close pair; pressure keeps pairs apart.
          const Vec3 g = D.grad(rij, r2) * (ps.volume[j] * gradScale_);
          f += Si.times(g) + Sj.times(g);
        }
        ps.force[i] += f * ps.volume[i];
      }
    });
  }

  struct Sym {  // symmetric 3x3
    Real xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
    bool zero() const { return xx == 0 && yy == 0 && zz == 0 && xy == 0 && xz == 0 && yz == 0; }
    Vec3 times(const Vec3& v) const {
      return {xx * v.x + xy * v.y + xz * v.z, xy * v.x + yy * v.y + yz * v.z, xz * v.x + yz * v.y + zz * v.z};
    }
  };
  std::vector<Sym> stress_;

 public:

 private:
  std::vector<Real> sigma_;  // phaseCount x phaseCount, N/m
  size_t phaseCount_;
  Real threshold_;
  Model model_;
  Real spacing_, dtLimit_;
  Real gradScale_ = 1, scaleH_ = 0;
  std::vector<Vec3> normal_;
  std::vector<Real> lap_, sigma_i_;
};

class SurfaceTension final : public Effect {
 public:
  enum class Curvature { Laplacian = 0, Divergence = 1, Fit = 2 };
  SurfaceTension(std::vector<Real> sigma, Real threshold, Real wallColour, Curvature curvature, Real spacing,
                 Real dtLimit)
      : sigma_(std::move(sigma)),
        threshold_(threshold),
        wallColour_(wallColour),
        curvature_(curvature),
        spacing_(spacing),
        dtLimit_(dtLimit) {}
  const char* name() const override { return "surface_tension"; }
  AttributeMask requiredAttributes() const override { return bit(Attribute::SurfaceColour); }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const Poly6Derivatives D(ctx.kernels);
    const SphKernels& K = ctx.kernels;
    if (lapResidual_ != lapResidual_ || residualH_ != K.h) {
      // sum_j V lap W over the rest lattice, self included: zero for an exact Laplacian.
      const Real s = spacing_, V = 1.0 / latticeKernelSum(K, s);
      const Real sum = sumOverRestLattice(K, s, [&](int a, int b, int c) {
        const Real r2 = s * s * Real(a * a + b * b + c * c);
        return r2 < K.h2 ? V * D.lap(r2) : 0.0;
      });
      lapResidual_ = sum;
      gradScale_ = colourGradientScale(K, s);
      faceArea_ = latticeFaceArea(K, s);
      residualH_ = K.h;
    }
    const Real lapSelf = D.lap(0);
    const NeighborLists& nf = ctx.fluidNeighbors;
    const NeighborLists& nb = ctx.boundaryNeighbors;
    const size_t n = ps.size();
    normal_.resize(n);
    lap_.resize(n);
    sigma_i_.resize(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const auto& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Vec3 xi = ps.position[i];
        const Real ci = ps.surfaceColour[i];
        Vec3 grad;
        Real lap = ps.volume[i] * ci * lapSelf - ci * lapResidual_;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
          const Real r2 = lengthSquared(rij);
          if (r2 >= K.h2) continue;
          const Real Vc = ps.volume[j] * ps.surfaceColour[j];
          grad += D.grad(rij, r2) * Vc;  // eq. 3
          lap += Vc * D.lap(r2);         // eq. 4
        }
        if (wallColour_ != 0)
          for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
            const uint32_t b = nb.indices[k];
            const Vec3 rib = ctx.periodic.separation(xi, ctx.boundary.position[b]);
            const Real r2 = lengthSquared(rib);
            if (r2 >= K.h2) continue;
            const Real Vc = ctx.boundary.volume[b] * wallColour_;
            grad += D.grad(rib, r2) * Vc;
            lap += Vc * D.lap(r2);
          }
        normal_[i] = grad * gradScale_;
        lap_[i] = lap;
        sigma_i_[i] = sigma_[ps.phase[i]];
      }
    });
    if (curvature_ == Curvature::Fit) applyFittedForce(ctx, ps, threshold_ / K.h);
    else applyTensionForce(ctx, ps, normal_, lap_, sigma_i_, threshold_ / K.h, curvature_ == Curvature::Divergence);
  }

  Real maxTimeStep(const StepContext&, const ParticleSet&) const override { return dtLimit_; }

 private:
  /// The part of a flat lattice face's surface band the threshold keeps, s sum_L |n_L| over the
  /// layers L whose |n| passes it: the CSF force sigma kappa |n| V summed across a band that
  /// holds all of it gives sigma kappa per unit area, one the threshold cuts gives that much of it.
  Real latticeFaceArea(const SphKernels& K, Real s) const {
    const Poly6Derivatives D(K);
    const Real V = 1.0 / latticeKernelSum(K, s), minNormal = threshold_ / K.h;
    Real area = 0;
    for (int layer = 0; layer <= int(std::ceil(K.h / s)); ++layer) {
      // The particle `layer` spacings below the face; its neighbours at offsets (a, b, c) s
      // exist where they are not above the face, b <= layer.
      const Real ny = gradScale_ * sumOverRestLattice(K, s, [&](int a, int b, int c) {
                        const Real r2 = s * s * Real(a * a + b * b + c * c);
                        if (b > layer || r2 >= K.h2 || r2 == 0) return 0.0;
                        return V * D.grad(Vec3(-a * s, -b * s, -c * s), r2).y;
                      });
      if (std::fabs(ny) > minNormal) area += s * std::fabs(ny);
    }
    return area;
  }

  /// F_i = sigma kappa n_i V_i / a (CSF with a fitted curvature; a the face's share of the band,
  /// latticeFaceArea). kappa = k1 + k2 of the quadric through the surface particles within h
  /// whose normals face the same way (surface_fit.h). The particles' centres lie half a spacing
  /// inside the liquid they stand for, so each principal curvature is moved out by s/2 (the
  /// parallel surface: k / (1 + k s/2)), and bounded by 1/s, the sharpest bend the lattice resolves.
  void applyFittedForce(const StepContext& ctx, ParticleSet& ps, Real minNormal) {
    const SphKernels& K = ctx.kernels;
    const NeighborLists& nf = ctx.fluidNeighbors;
    const Real minNormal2 = minNormal * minNormal, s = spacing_, kMax = 1 / s;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 256), [&](const auto& range) {
      std::vector<SurfacePoint> points;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Real nl2 = lengthSquared(normal_[i]);
        if (sigma_i_[i] == 0 || nl2 <= minNormal2) continue;
        const Vec3 ni = normal_[i] / std::sqrt(nl2), xi = ps.position[i];
        points.assign(1, SurfacePoint{Vec3{}, 1});
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Real nj2 = lengthSquared(normal_[j]);
          if (nj2 <= minNormal2 || dot(normal_[j], ni) <= 0.5 * std::sqrt(nj2)) continue;
          const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
          const Real q = 1 - lengthSquared(rij) / K.h2;
          if (q <= 0) continue;
          points.push_back({-rij, q * q * q});
        }
        const PrincipalCurvatures pc = fitSurfaceCurvatures(ni, points.data(), points.size(), K.h);
        if (!pc.valid) continue;
        Real kappa = 0;
        for (Real k : {pc.k1, pc.k2}) {
          k = std::clamp(k, -kMax, kMax);
          kappa += std::clamp(k / (1 + k * s / 2), -kMax, kMax);
        }
        ps.force[i] += normal_[i] * (sigma_i_[i] * kappa * ps.volume[i] / faceArea_);
      }
    });
  }

  std::vector<Real> sigma_;  // per phase, N/m
  Real threshold_, wallColour_;
  Curvature curvature_;
  Real spacing_, dtLimit_;
  std::vector<Vec3> normal_;
  std::vector<Real> lap_, sigma_i_;
  Real lapResidual_ = std::numeric_limits<Real>::quiet_NaN(), residualH_ = 0, gradScale_ = 1, faceArea_ = 1;
};

}  // namespace

EffectInfo interfaceTensionInfo() {
  EffectInfo info{
      "interface_tension",
      "tension at fluid-fluid interfaces, -sigma_i lap(c_i) n/|n| (eqs. 3, 4); c_i per phase (interface_colour)",
      {{"sigma", 1, 0, 1e4, {0.0}, "N/m", "interface tension of every pair of unlike fluids (pairs below override)"},
       {"normal_threshold", 1, 0, 10, {0.0}, "1/h", "force only where |grad c| > threshold / h (the stress model needs none: it vanishes with |n|)"},
       {"model", 1, 0, 2, {2.0}, "", "2: capillary stress (Hu & Adams 2006); 1: sigma kappa n, kappa = -div(n/|n|) (Morris 2000); 0: the paper's -sigma lap(c) n/|n| (eq. 4)", 0, true},
       {"time_step_factor", 1, 1e-3, 10, {1.0}, "", "dt <= factor sqrt(rho dx^3 / (2 pi sigma)) (Brackbill)"}},
      [](const EffectSpec& spec, const Scene& scene) {
        const size_t n = scene.phases.size();
        std::vector<Real> sigma(n * n, spec.number("sigma"));
        for (const ParamValues& pair : spec.list("pair")) {
          const auto& idx = pair.params.at("phases");
          const size_t a = size_t(idx.at(0)), b = size_t(idx.at(1));
          sigma[a * n + b] = sigma[b * n + a] = pair.number("sigma");
        }
        const Real sigmaMax = *std::max_element(sigma.begin(), sigma.end());
        return std::make_unique<InterfaceTension>(
            sigma, n, spec.number("normal_threshold"), InterfaceTension::Model(int(spec.number("model") + 0.5)),
            scene.solver.particleSpacing, spec.number("time_step_factor") * capillaryTimeStep(scene, sigmaMax));
      }};
  info.lists = {{"pair",
                 "interface tension of one pair of fluids",
                 {{"phases", 2, 0, 0, {}, "", "the two fluids, e.g. [\"water\", \"oil\"]", 2},
                  {"sigma", 1, 0, 1e4, {}, "N/m", "their interface tension"}}}};
  info.phaseKeys = {"interface_colour"};
  return info;
}

EffectInfo surfaceTensionInfo() {
  EffectInfo info{
      "surface_tension",
      "tension at free surfaces, sigma_s kappa n with n = grad c_s (eq. 3; CSF); sigma_s per phase (surface_tension)",
      {{"normal_threshold", 1, -1, 10, {-1.0}, "1/h", "force only where |grad c_s| > threshold / h; -1: 0.6 with the fitted curvature (the lattice face's outer layer reads 1), 0.2 with the others"},
       {"curvature", 1, -1, 2, {-1.0}, "", "2: kappa of a quadric fitted to the surface particles (surface_fit.h); 1: kappa = -div(n/|n|) (Morris 2000); 0: the paper's lap(c) (eq. 4); -1: 2 on DFSPH, 1 on WCSPH (where the fit leaves a static drop at 0.3-0.9 of Laplace's pressure)", 0, true},
       {"wall_colour", 1, 0, 1, {1.0}, "", "colour the walls count as: 1 like liquid, 0 like gas"},
       {"time_step_factor", 1, 1e-3, 10, {1.0}, "", "dt <= factor sqrt(rho dx^3 / (2 pi sigma)) (Brackbill)"}},
      [](const EffectSpec& spec, const Scene& scene) {
        std::vector<Real> sigma;
        for (const PhaseSpec& p : scene.phases) sigma.push_back(p.surfaceTension);
        const Real sigmaMax = *std::max_element(sigma.begin(), sigma.end());
        int curvature = int(std::lround(spec.number("curvature")));
        if (curvature < 0) curvature = scene.solver.pressure == PressureSolverChoice::DFSPH ? 2 : 1;
        Real threshold = spec.number("normal_threshold");
        if (threshold < 0) threshold = curvature == 2 ? 0.6 : 0.2;
        return std::make_unique<SurfaceTension>(sigma, threshold, spec.number("wall_colour"),
                                                SurfaceTension::Curvature(curvature), scene.solver.particleSpacing,
                                                spec.number("time_step_factor") * capillaryTimeStep(scene, sigmaMax));
      }};
  info.phaseKeys = {"surface_colour", "surface_tension"};
  return info;
}

}  // namespace mf::effects
