// A scene file as every stage reads it: the simulation's Scene (sim/), and the surfacing and
// render stages' own settings, each parsed by its stage. All problems of the file are collected
// into one SceneError, so that a bad [render] key stops `multifluid sim` before anything runs.
#pragma once

#include <string>
#include <vector>

#include "render/settings.h"
#include "sim/scene_budget.h"
#include "sim/scene_file.h"
#include "surfacing/settings.h"

namespace mf {

struct SceneStages {
  Scene scene;                  // what the simulation reads
  SurfacingSettings surfacing;  // [surfacing]
  RenderSettings render;        // [render]

  /// What the later stages add to the budget (sim/scene_budget.h).
  LaterStageSizes laterSizes() const { return {surfacing.voxelRatio, double(render.width), double(render.height)}; }
};

/// As parseScene (sim/scene_file.h), with [surfacing] and [render] read by their stages.
SceneStages parseSceneStages(const std::string& text, const std::string& sourceName,
                             const std::vector<std::string>& overrides = {});

/// parseSceneStages of readSceneSource(pathOrName): a path or an embedded scene's name.
SceneStages loadSceneStages(const std::string& pathOrName, const std::vector<std::string>& overrides = {});

}  // namespace mf
