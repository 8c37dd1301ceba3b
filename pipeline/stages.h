// The stages of a run into one folder: sim -> surface -> render (and preview) -> encode. Each
// skips the frames whose completion record verifies, redoes the rest, and records what it wrote.
#pragma once

#include <filesystem>
#include <string>

#include "render/preview.h"
#include "sim/scene.h"

namespace mf::pipeline {

struct StageOptions {
  int firstFrame = 0, lastFrame = -1;  // lastFrame -1: the scene's last
  int threads = 0;                     // 0: all cores
  bool sim = true, surface = true, render = true, preview = false, encode = true;
  render::PreviewColour previewColour = render::PreviewColour::Phase;
  double maxStepsPerFrame = 1e5;       // a run whose dt collapses stops here (0: no bound)
};

/// Runs the chosen stages of `scene` into `out` while holding the folder's lock; prints progress
/// and returns 0, or throws. Appends the summary to out/run.log.
int runStages(const Scene& scene, const StageOptions& options, const std::filesystem::path& out);

}  // namespace mf::pipeline
