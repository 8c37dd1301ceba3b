// Symmetric pressure force, Mueller et al. 2005 eq. (5), written per particle as a force:
//   F_i = -V_i sum_j V_j (p_i + p_j)/2 grad W_spiky(x_i - x_j)
// with V = m/rho (eq. 1) or 1/(number density) (Solenthaler & Pajarola 2008). The pair term is
// antisymmetric in i and j, so pressure conserves linear momentum exactly up to rounding.
// Walls (Akinci et al. 2012): a boundary sample b acts as a mirrored particle of pressure p_i
// and volume rho0_i V_b / rho_i:  F_i -= V_i sum_b (rho0_i V_b / rho_i) p_i grad W.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "builtin.h"

namespace mf::effects {

namespace {

class Pressure final : public Effect {
 public:
  explicit Pressure(Real wallScale) : wallScale_(wallScale) {}
  const char* name() const override { return "pressure"; }

  void accumulateForces(const StepContext& ctx, ParticleSet& ps) override {
    const SphKernels& K = ctx.kernels;
    const Vec3* x = ps.position.data();
    const Real* V = ps.volume.data();
    const Real* p = ps.pressure.data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 512), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const Vec3 xi = x[i];
        const Real pi = p[i];
        Vec3 sum;
        const NeighborLists& nf = ctx.fluidNeighbors;
        for (uint64_t k = nf.begin(i), e = nf.end(i); k < e; ++k) {
          const uint32_t j = nf.indices[k];
          const Vec3 rij = xi - x[j];
          const Real rl = std::sqrt(lengthSquared(rij));
          sum += K.spikyGrad(rij, rl) * (V[j] * 0.5 * (pi + p[j]));
        }
        const NeighborLists& nb = ctx.boundaryNeighbors;
        if (nb.count(i) > 0 && pi != 0) {
          const Real mirror = wallScale_ * ps.restDensity[i] / ps.density[i] * pi;
          for (uint64_t k = nb.begin(i), e = nb.end(i); k < e; ++k) {
            const uint32_t b = nb.indices[k];
            const Vec3 rib = xi - ctx.boundary.position[b];
            sum += K.spikyGrad(rib, std::sqrt(lengthSquared(rib))) * (ctx.boundary.volume[b] * mirror);
          }
        }
        ps.force[i] -= sum * V[i];
      }
    });
  }

 private:
  Real wallScale_;
};

}  // namespace

EffectInfo pressureInfo() {
  return {"pressure",
          "state equation P = k (rho - rho0) and the symmetric pressure force (eq. 5), walls by Akinci 2012",
          {{"wall_scale", 1, 0, 10, {1.0}, "", "multiplier on the wall repulsion (1 = Akinci 2012)"}},
          [](const EffectSpec& spec, const Scene&) {
            return std::make_unique<Pressure>(spec.number("wall_scale"));
          }};
}

}  // namespace mf::effects
