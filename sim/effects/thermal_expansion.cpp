// Rest density from temperature (Mueller et al. 2005, section 4.2: the lava lamp):
//   rho0(T) = rho0_ref / (1 + beta (T - T_ref))
// per phase, so a heated fluid takes more volume for the same mass and rises. Mass is kept.
// The denominator is held above 0.1 (a tenfold expansion) so that a wild temperature cannot
// make the rest density negative or infinite; the scene reader bounds beta.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "builtin.h"

namespace mf::effects {

namespace {

class ThermalExpansion final : public Effect {
 public:
  explicit ThermalExpansion(std::vector<PhaseSpec> phases) : phases_(std::move(phases)) {}
  const char* name() const override { return "thermal_expansion"; }
  AttributeMask requiredAttributes() const override { return bit(Attribute::Temperature); }
  void accumulateForces(const StepContext&, ParticleSet&) override {}
  void prepare(ParticleSet& ps) override { update(ps); }
  void advance(const StepContext&, ParticleSet& ps, Real) override { update(ps); }

 private:
  void update(ParticleSet& ps) const {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ps.size(), 4096), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        const PhaseSpec& p = phases_[ps.phase[i]];
        if (p.thermalExpansion == 0) continue;
        const Real expansion = 1 + p.thermalExpansion * (ps.temperature[i] - p.referenceTemperature);
        ps.restDensity[i] = p.restDensity / std::max(Real(0.1), expansion);
      }
    });
  }
  std::vector<PhaseSpec> phases_;
};

}  // namespace

EffectInfo thermalExpansionInfo() {
  EffectInfo info{"thermal_expansion",
                  "rest density falls as temperature rises: rho0(T) = rest_density / (1 + beta (T - T_ref)), beta and "
                  "T_ref per phase (thermal_expansion, reference_temperature)",
                  {},
                  [](const EffectSpec&, const Scene& scene) { return std::make_unique<ThermalExpansion>(scene.phases); }};
  info.phaseKeys = {"thermal_expansion", "reference_temperature"};
  return info;
}

}  // namespace mf::effects
