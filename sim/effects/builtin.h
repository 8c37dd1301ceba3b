// Factories of the effects that ship with the simulator; effectRegistry() lists them.
#pragma once

#include <memory>

#include "../effect.h"

namespace mf::effects {

EffectInfo gravityInfo();
EffectInfo pressureInfo();
EffectInfo viscosityInfo();
EffectInfo dampingInfo();
EffectInfo interfaceTensionInfo();
EffectInfo surfaceTensionInfo();
EffectInfo heatDiffusionInfo();
EffectInfo dyeDiffusionInfo();
EffectInfo thermalExpansionInfo();
EffectInfo buoyancyInfo();
EffectInfo flameHeatingInfo();
EffectInfo phaseChangeInfo();
EffectInfo trappedAirInfo();
EffectInfo emitterInfo();

}  // namespace mf::effects
