// The stages of a run into one folder: sim -> surface -> render (and preview) -> encode. Each
// skips the frames whose completion record verifies, redoes the rest, and records what it wrote.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "render/preview.h"
#include "pipeline/scene_stages.h"

namespace mf::pipeline {

struct StageOptions {
  int firstFrame = 0, lastFrame = -1;  // lastFrame -1: the scene's last
  int threads = 0;                     // 0: all cores
  bool sim = true, surface = true, render = true, preview = false, encode = true;
  render::PreviewColour previewColour = render::PreviewColour::Phase;
  double maxStepsPerFrame = 1e5;       // a run whose dt collapses stops here (0: no bound)
  // Surface, render, preview: how long to wait for an input frame that another process (a farm's
  // simulation job) has not finished yet; 0: skip it. A frame still missing then is an error.
  double waitForInputSeconds = 0;
};

/// An input frame was still missing after --wait-for-input (exit status 75, EX_TEMPFAIL: a farm
/// task then gives its CPUs back and is requeued, so that it never starves the simulation).
struct InputNotReady : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The simulation stopped at a step boundary because of SIGTERM or SIGUSR1 (a farm's time limit
/// or preemption); the checkpoint of the last finished frame is intact, and a re-run resumes.
struct StopRequested : std::runtime_error {
  int signal;
  StopRequested(const std::string& what, int sig) : std::runtime_error(what), signal(sig) {}
};

/// Runs the chosen stages of `scene` into `out` while holding the locks of those stages and
/// frames (folder_lock.h), so that other stages or frames may run alongside; prints progress
/// and returns 0, or throws. Appends the summary to out/run.log.
int runStages(const SceneStages& stages, const StageOptions& options, const std::filesystem::path& out);

}  // namespace mf::pipeline
