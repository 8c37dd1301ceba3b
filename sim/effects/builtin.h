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

/// The factor that makes the tensions' colour gradient (poly6's, in the effects' pair sums) exact
/// for a linear field on the rest lattice of `spacing`: 1 / 1.0668 at h = 2 spacings. Without it
/// the gradient, and so the interface's delta function, reads 6.7 % high there.
Real colourGradientScale(const SphKernels& kernels, Real spacing);

}  // namespace mf::effects
