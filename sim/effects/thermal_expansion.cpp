// Rest density from temperature (Mueller et al. 2005, section 4.2: the lava lamp):
//   rho0(T) = rho0_ref / (1 + beta (T - T_ref))
// per phase, so a heated fluid takes more volume for the same mass and rises. Mass is kept.
// The denominator is held above 0.1 (a tenfold expansion) so that a wild temperature cannot
// make the rest density negative or infinite; the scene reader bounds beta.
// boussinesq = 1 (Boussinesq approximation): the rest density stays at rest_density and the
// particle's weight is scaled instead, f = m g (rho0(T)/rest_density - 1) on top of gravity,
// so a heated particle weighs what a particle of density rho0(T) and the same volume would.
// Why: SPH can only express the volume form's buoyancy by moving particles apart, and the
// particle lattice resists that (the lava lamp's wax, heated at the floor, expands upward as
// a column and never rises as a blob: docs/scenes.md, lava lamp). The weight form needs no
// rearrangement, keeps the particle spacing and resolution where the wax is hottest, and lets
// beta be large without crushing a hot particle among cold ones.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "builtin.h"

namespace mf::effects {

namespace {

class ThermalExpansion final : public Effect {
 public:
  ThermalExpansion(std::vector<PhaseSpec> phases, bool boussinesq, const Vec3& g)
      : phases_(std::move(phases)), boussinesq_(boussinesq), g_(g) {}
  const char* name() const override { return "thermal_expansion"; }
  AttributeMask requiredAttributes() const override { return bit(Attribute::Temperature); }
  void accumulateForces(const StepContext&, ParticleSet& ps) override {
    if (!boussinesq_) return;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 4096), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const PhaseSpec& p = phases_[ps.phase[i]];
        if (p.thermalExpansion == 0) continue;
        ps.force[i] += g_ * (ps.mass[i] * (1 / expansion(p, ps.temperature[i]) - 1));
      }
    });
  }
  void prepare(ParticleSet& ps) override { update(ps); }
  void advance(const StepContext&, ParticleSet& ps, Real) override { update(ps); }

 private:
  static Real expansion(const PhaseSpec& p, Real T) {
    return std::max(Real(0.1), 1 + p.thermalExpansion * (T - p.referenceTemperature));
  }
  void update(ParticleSet& ps) const {
    if (boussinesq_) return;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 4096), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const PhaseSpec& p = phases_[ps.phase[i]];
        if (p.thermalExpansion == 0) continue;
        ps.restDensity[i] = p.restDensity / expansion(p, ps.temperature[i]);
      }
    });
  }
  std::vector<PhaseSpec> phases_;
  bool boussinesq_;
  Vec3 g_;
};

}  // namespace

EffectInfo thermalExpansionInfo() {
  EffectInfo info{"thermal_expansion",
                  "rest density falls as temperature rises: rho0(T) = rest_density / (1 + beta (T - T_ref)), beta and "
                  "T_ref per phase (thermal_expansion, reference_temperature)",
                  {{"boussinesq", 1, 0, 1, {0.0}, "", "1: keep the rest density and scale the particle's weight by rho0(T)/rest_density instead"}},
                  [](const EffectSpec& spec, const Scene& scene) {
                    const EffectSpec* g = scene.effect("gravity");
                    return std::make_unique<ThermalExpansion>(scene.phases, spec.number("boussinesq") > 0.5,
                                                              g ? g->vector("acceleration") : Vec3{});
                  }};
  info.phaseKeys = {"thermal_expansion", "reference_temperature"};
  return info;
}

}  // namespace mf::effects
