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
      effects::dampingInfo(),
      effects::heatDiffusionInfo(),
      effects::dyeDiffusionInfo(),
      effects::thermalExpansionInfo(),
  };
  return registry;
}

const EffectInfo* findEffect(const std::string& name) {
  for (const EffectInfo& e : effectRegistry())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace mf
