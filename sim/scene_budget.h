// What a scene will cost, estimated from its keys before anything is allocated: particles, wall
// samples, memory and time steps per frame. A scene over the machine's memory (or --max-memory),
// one that seeds no particle, or one whose time step at rest would need more than a bound of steps
// per frame, is refused with a SceneError naming the file, line and key to change.
#pragma once

#include <string>

#include "scene.h"

namespace mf {

struct SceneBudget {
  double particles = 0;        // seeded at the start (fluid blocks' lattices inside the domain)
  double emitted = 0;          // what emitters can add over the scene
  double boundarySamples = 0;  // wall samples of the solids
  double surfaceVoxels = 0;    // narrow-band voxels of the surfacing stage, at most
  double memoryBytes = 0;      // the largest stage
  double restTimeStep = 0;     // dt at rest: the smallest of the sound, viscous, diffusive, capillary limits
  std::string timeStepLimiter; // which limit, and its key
  double stepsPerFrame = 0;
};

struct BudgetLimits {
  double maxMemoryBytes = 0;       // 0: 80 % of the physical memory (and of RLIMIT_AS where set)
  double maxStepsPerFrame = 1e5;   // 0: no bound
  bool force = false;              // run over the step bound anyway
};

/// What the later stages' settings add to the estimate (surfacing/settings.h, render/settings.h;
/// their defaults here): the level sets' voxel size and the image's pixels.
struct LaterStageSizes {
  double voxelRatio = 0.5;  // surfacing.voxel_ratio
  double width = 480, height = 270;  // render.width, render.height
};

/// The estimate alone (never throws; no allocation that grows with the scene).
SceneBudget estimateSceneBudget(const Scene& scene, const LaterStageSizes& later = {});

/// The estimate, checked against the limits; throws SceneError listing every problem.
SceneBudget checkSceneBudget(const Scene& scene, const BudgetLimits& limits = {}, const LaterStageSizes& later = {});

/// The memory a run may use by default: 80 % of the physical memory, or of RLIMIT_AS if lower.
double defaultMemoryLimit();

}  // namespace mf
