// Symmetric pressure force, Mueller et al. 2005 eq. (5), written per particle as a force:
//   F_i = -V_i sum_j V_j (p_i + p_j) grad W_spiky(x_i - x_j)
// with V = m/rho (eq. 1) or 1/(number density) (Solenthaler & Pajarola 2008).
// Eq. (5) as printed averages the pair pressure, (p_i + p_j)/2. Inside a fluid
// sum_j V_j grad W_ij = 0, so that form yields only half of grad p: a settled column would
// carry twice the hydrostatic pressure. The pair sum p_i + p_j (Monaghan's symmetric form for
// equal volumes) gives grad p itself; the pair term stays antisymmetric in i and j, so linear
// momentum is conserved up to rounding (tested).
// Walls (Akinci et al. 2012, eq. 10): a boundary sample b pushes with the particle's own
// pressure and volume rho0_i V_b / rho_i:  F_i -= V_i sum_b (rho0_i V_b / rho_i) p_i grad W.
// This is the force that follows from the wall's share rho0_i sum_b V_b W_ib of the density.
// grad W is the gradient of the density kernel (Wendland C2) by default, so that the force is
// minus the gradient of the elastic energy of the SPH density and a closed box only loses
// energy; solver.kernel = "muller2003" restores the papers' spiky gradient (sim/kernels.h).
// Hydrostatic reference (reference_density > 0): the pair and wall sums use the perturbation
// p' = p - p_ref with p_ref = rho_ref |g| (level - height) below `reference_level` (0 above,
// bent smoothly across one kernel radius around it; with follow_content, a level per container
// that follows its content; hydrostatic_reference.h), and the exact -V_i grad p_ref (upward) is
// added as a body force. The sum is the same momentum equation,
// rho a = -grad p' + (rho - rho_ref) g. Why: the pair sum's
// p_i sum_j V_j grad W_ij term, zero only on a perfect lattice, gives the particle arrangement
// a rigidity proportional to the pressure itself; at 10 cm depth that is ~1 kPa against the
// ~15 Pa a lone oil particle's buoyancy exerts over its own size, so the lattice cages it.
// Choice (docs/method.md, hydrostatic reference): rho_ref the densest liquid and the level where a
// column of it weighs what the liquids weigh; then p' = 0 at the floor and dp'/dy >= 0 above,
// so p' never turns tensile, in any arrangement of the liquids.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "builtin.h"
#include "sim/hydrostatic_reference.h"

namespace mf::effects {

namespace {

struct Mat3 {
  Real m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 operator*(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  void addOuter(const Vec3& a, const Vec3& b, Real w) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] += w * a[r] * b[c];
  }
  Real det() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  Mat3 inverse() const {
    const Real d = 1 / det();
    Mat3 r;
    r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * d;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * d;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * d;
    r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * d;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * d;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * d;
    r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * d;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * d;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * d;
    return r;
  }
};

class Pressure final : public Effect {
 public:
  Pressure(Real wallScale, bool correctGradient, const HydrostaticReference& reference)
      : wallScale_(wallScale), correct_(correctGradient), ref_(reference) {}
  const char* name() const override { return "pressure"; }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const SphKernels& K = ctx.kernels;
    const Vec3* x = ps.position.data();
    const Real* V = ps.volume.data();
    const Real* p = ps.pressure.data();
    const NeighborLists& nf = ctx.fluidNeighbors;
    const NeighborLists& nb = ctx.boundaryNeighbors;
    if (correct_) computeCorrection(ctx, ps);
    const Mat3* L = correct_ ? correction_.data() : nullptr;
    if (ref_.active()) {
      ref_.follow(ps, ctx.particleSpacing);
      perturbation_.resize(ps.size());
      refSlope_.resize(ps.size());
      tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 2048), [&](const auto& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          // one walk over the containers per particle
          const HydrostaticReference::Profile at = ref_.profile(ref_.depth(x[i]));
          refSlope_[i] = at.slope;
          perturbation_[i] = p[i] - ref_.weight * at.head;
        }
      });
      p = perturbation_.data();
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 512), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Vec3 xi = x[i];
        const Real pi = p[i];
        Vec3 sum;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Vec3 rij = ctx.periodic.separation(xi, x[j]);
          const Vec3 grad = K.pressureGrad(rij, lengthSquared(rij));
          // (L_i + L_j)/2 keeps the pair term antisymmetric.
          const Vec3 g = L ? (L[i] * grad + L[j] * grad) * 0.5 : grad;
          sum += g * (V[j] * (pi + p[j]));
        }
        if (nb.count(i) > 0 && pi != 0) {
          const Real mirror = wallScale_ * ps.restDensity[i] / ps.density[i] * pi;
          Vec3 wall;
          for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
            const uint32_t b = nb.indices[k];
            const Vec3 rib = ctx.periodic.separation(xi, ctx.boundary.position[b]);
            wall += K.pressureGrad(rib, lengthSquared(rib)) * (ctx.boundary.volume[b] * mirror);
          }
          sum += L ? L[i] * wall : wall;
        }
        ps.force[i] -= sum * V[i];
        if (ref_.active() && refSlope_[i] > 0) ps.force[i] += ref_.up * (ref_.weight * refSlope_[i] * V[i]);
      }
    });
  }

 private:
  // L_i = (sum_j V_j (x_j - x_i) (x) grad W_ij)^-1 over fluid and wall neighbours (Bonet & Lok
  // 1999): makes the discrete gradient exact for linear pressure fields whatever the particle
  // arrangement. Where the neighbourhood is too incomplete for the inverse to be trusted (near
  // a free surface), the correction fades to the identity.
  void computeCorrection(const StepContext& ctx, const ParticleSet& ps) {
    const SphKernels& K = ctx.kernels;
    correction_.resize(ps.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 512), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        Mat3 A;
        for (auto& row : A.m)
          for (Real& v : row) v = 0;
        const Vec3 xi = ps.position[i];
        const NeighborLists& nf = ctx.fluidNeighbors;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Vec3 rij = ctx.periodic.separation(xi, ps.position[j]);
          A.addOuter(-rij, K.pressureGrad(rij, lengthSquared(rij)), ps.volume[j]);
        }
        const NeighborLists& nb = ctx.boundaryNeighbors;
        const Real wallVolume = ps.restDensity[i] / ps.density[i];
        for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
          const uint32_t b = nb.indices[k];
          const Vec3 rib = ctx.periodic.separation(xi, ctx.boundary.position[b]);
          A.addOuter(-rib, K.pressureGrad(rib, lengthSquared(rib)), wallVolume * ctx.boundary.volume[b]);
        }
        const Real d = A.det();
        Mat3 L;  // identity
        // Full correction only for well-filled neighbourhoods (det(A) >= 0.8), fading to none
        // at 0.6: near free surfaces and in sparse spray the inverse amplifies noise.
        const Real w = std::clamp((d - 0.6) / 0.2, Real(0), Real(1));
        if (w > 0) {
          const Mat3 inv = A.inverse();
          for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) L.m[a][c] = w * inv.m[a][c] + (1 - w) * (a == c ? 1 : 0);
        }
        correction_[i] = L;
      }
    });
  }

  Real wallScale_;
  bool correct_;
  HydrostaticReference ref_;
  std::vector<Mat3> correction_;
  std::vector<Real> perturbation_;
  std::vector<Real> refSlope_;  // d p_ref / d depth / weight: 1 below the level's bend, 0 above it
};

}  // namespace

EffectInfo pressureInfo() {
  EffectInfo info{"pressure",
          "state equation P = k (rho - rho0) and the symmetric pressure force (eq. 5), walls by Akinci 2012",
          {{"wall_scale", 1, 0, 10, {1.0}, "", "multiplier on the wall repulsion (1 = Akinci 2012)"},
           {"gradient_correction", 1, 0, 1, {0.0}, "", "1: symmetric kernel-gradient correction, exact for linear pressure fields (settled pressure error ~1 % instead of ~4 %, about 45 % more time per step); 0: plain kernel gradient"},
           {"reference_density", 1, 0, 1e5, {0.0}, "kg/m^3", "hydrostatic reference subtracted from the pressure in the pair forces and added back exactly as a body force (0: none); the densest liquid's rest density with reference_level where a column of it weighs what the liquids weigh keeps the remainder repulsive"},
           {"reference_level", 1, -1e4, 1e4, {0.0}, "m", "height (along -gravity) of the free surface: the reference pressure grows as rho_ref |g| depth below it and is 0 above, bent smoothly across one kernel radius around it"},
           {"follow_content", 1, 0, 1, {0.0}, "", "1: each container's level follows what it holds, every step: where a column of the reference liquid would weigh the container's particles, less one spacing (a glass that fills or empties; reference_level is not read)", 0, true}},
          [](const EffectSpec& spec, const Scene& scene) {
            return std::make_unique<Pressure>(spec.number("wall_scale"), spec.number("gradient_correction") > 0.5,
                                              HydrostaticReference::of(spec, scene));
          }};
  info.check = [](const EffectSpec& spec, const Scene& scene) {
    std::vector<std::pair<std::string, std::string>> problems;
    const EffectSpec* g = scene.effect("gravity");
    if (spec.number("reference_density") > 0 && (!g || lengthSquared(g->vector("acceleration")) == 0))
      problems.push_back({"reference_density", "has no effect without [effects.gravity] (a hydrostatic reference needs gravity)"});
    if (spec.number("follow_content") > 0.5) {
      if (spec.number("reference_density") == 0) problems.push_back({"follow_content", "needs reference_density > 0 (the liquid whose column is measured)"});
      if (scene.solids.empty()) problems.push_back({"follow_content", "needs a container ([[solid]]): the level is measured per container"});
      if (g && (g->vector("acceleration").x != 0 || g->vector("acceleration").z != 0))
        problems.push_back({"follow_content", "needs gravity along -y (containers stand on the y axis)"});
      if (spec.number("reference_level") != 0)
        problems.push_back({"reference_level", "is not read with follow_content = 1 (the level follows the content): remove one of the two"});
    }
    // A scene that names no solver runs on DFSPH, whose implicit solve is the pressure force:
    // WCSPH's keys there say the scene was written for the state equation.
    if (scene.solver.pressure == PressureSolverChoice::DFSPH && !scene.solver.pressureNamed) {
      if (spec.number("wall_scale") != 1) problems.push_back({"wall_scale", kWcsphKeyUnnamed});
      if (spec.number("gradient_correction") != 0) problems.push_back({"gradient_correction", kWcsphKeyUnnamed});
      if (spec.number("reference_density") == 0)
        problems.push_back({"reference_density", std::string("missing: without it the table ") + kWcsphKeyUnnamed});
    }
    return problems;
  };
  return info;
}

}  // namespace mf::effects
