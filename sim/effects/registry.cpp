#include "builtin.h"

namespace mf {

const std::vector<EffectInfo>& effectRegistry() {
  // Order = the order the step loop runs the enabled effects in (fixed, for determinism).
  static const std::vector<EffectInfo> registry = {
      effects::gravityInfo(),
      effects::pressureInfo(),
      effects::viscosityInfo(),
      effects::interfaceTensionInfo(),
      effects::surfaceTensionInfo(),
      effects::buoyancyInfo(),
      effects::dampingInfo(),
      effects::heatDiffusionInfo(),
      effects::dyeDiffusionInfo(),
      effects::flameHeatingInfo(),
      effects::phaseChangeInfo(),  // after the heat has moved; before expansion sets water's rho0(T)
      effects::thermalExpansionInfo(),
      // Births and removals (editParticles) run after every advance(), in this order.
      effects::trappedAirInfo(),
      effects::emitterInfo(),
  };
  return registry;
}

const EffectInfo* findEffect(const std::string& name) {
  for (const EffectInfo& e : effectRegistry())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace mf
