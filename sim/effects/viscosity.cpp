// Viscosity force, Mueller et al. 2005 eq. (9), with the pairwise mixed viscosity:
//   F_i = V_i sum_j V_j (mu_i + mu_j)/2 (v_j - v_i) lap W_visc(x_i - x_j)
// Antisymmetric in i and j (momentum conserving); lap W_visc > 0, so it only damps relative
// motion. Walls get an optional no-slip drag of the same form with v_b = 0 and mu_b = mu_i.
// With the implicit pressure solver the same operator is integrated implicitly
// (implicit_viscosity.h) and sets no time step; with WCSPH it is an explicit force.
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "builtin.h"
#include "implicit_viscosity.h"

namespace mf::effects {

namespace {

class Viscosity final : public Effect {
 public:
  Viscosity(Real wallFriction, Real stabilityFactor, bool implicit)
      : wallFriction_(wallFriction), stabilityFactor_(stabilityFactor), implicit_(implicit) {}
  const char* name() const override { return "viscosity"; }

  std::string solveVelocities(const StepContext& ctx, ParticleSet& ps, Real dt) override {
    if (!implicit_) return {};
    // 1e-6 relative residual: far below the pressure solve's 5e-4 density tolerance.
    const ImplicitViscosityStats s = solveImplicitViscosity(ctx, ps, dt, wallFriction_, 1e-6, 500);
    ++solves_;
    explicit_ += s.explicitStep;
    iterations_ += uint64_t(s.iterations);
    if (s.converged) return {};
    return fmt::format("the implicit viscosity solve did not converge in {} iterations (relative residual {:.2g})", s.iterations, s.error);
  }

  std::vector<std::pair<std::string, double>> statistics() const override {
    if (!implicit_) return {};
    return {{"implicit viscosity: CG iterations per step", solves_ ? double(iterations_) / double(solves_) : 0.0},
            {"implicit viscosity: share of steps taken explicitly (max theta <= 1/2)", solves_ ? double(explicit_) / double(solves_) : 0.0}};
  }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    if (implicit_) return;  // solveVelocities applies it
    const SphKernels& K = ctx.kernels;
    const Vec3* x = ps.position.data();
    const Vec3* v = ps.velocity.data();
    const Real* V = ps.volume.data();
    const Real* mu = ps.viscosity.data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 512), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Vec3 xi = x[i], vi = v[i];
        const Real mui = mu[i];
        Vec3 sum;
        const NeighborLists& nf = ctx.fluidNeighbors;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Real rl = std::sqrt(lengthSquared(ctx.periodic.separation(xi, x[j])));
          sum += (v[j] - vi) * (V[j] * 0.5 * (mui + mu[j]) * K.viscosityLaplacian(rl));
        }
        if (wallFriction_ > 0) {
          const NeighborLists& nb = ctx.boundaryNeighbors;
          const Real scale = wallFriction_ * mui * ps.restDensity[i] / ps.density[i];
          for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
            const uint32_t b = nb.indices[k];
            const Real rl = std::sqrt(lengthSquared(ctx.periodic.separation(xi, ctx.boundary.position[b])));
            sum -= vi * (ctx.boundary.volume[b] * scale * K.viscosityLaplacian(rl));
          }
        }
        ps.force[i] += sum * V[i];
      }
    });
  }

  Real maxTimeStep(const StepContext& ctx, const ParticleSet& ps) const override {
    if (implicit_) return std::numeric_limits<Real>::infinity();  // backward Euler: no limit
    // Explicit diffusion limit dt <= factor h^2 / nu, nu = mu / rho0 (kinematic viscosity).
    Real nuMax = 0;
    for (size_t i = 0; i < ps.size(); ++i) nuMax = std::max(nuMax, ps.viscosity[i] / ps.restDensity[i]);
    return nuMax > 0 ? stabilityFactor_ * ctx.kernels.h2 / nuMax : std::numeric_limits<Real>::infinity();
  }

 private:
  Real wallFriction_, stabilityFactor_;
  bool implicit_;
  uint64_t solves_ = 0, iterations_ = 0, explicit_ = 0;
};

}  // namespace

EffectInfo viscosityInfo() {
  return {"viscosity",
          "mixed-viscosity force (eq. 9), mu per phase",
          {{"wall_friction", 1, 0, 10, {0.0}, "", "no-slip wall drag as a multiple of the fluid viscosity (0 = free slip)"},
           {"stability_factor", 1, 1e-3, 1, {0.125}, "", "dt <= factor h^2 rho0 / mu (explicit, with WCSPH)"}},
          [](const EffectSpec& spec, const Scene& scene) {
            return std::make_unique<Viscosity>(spec.number("wall_friction"), spec.number("stability_factor"),
                                               scene.solver.pressure == PressureSolverChoice::DFSPH);
          }};
}

}  // namespace mf::effects
