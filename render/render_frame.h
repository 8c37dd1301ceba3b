// One frame through the render stage: the surface file's level sets (and the scene's solids) in,
// a multi-layer linear EXR (beauty and AOVs, render/aov.h) and an sRGB PNG out; with
// render.denoise both show the denoised beauty (render/denoise.h), and the EXR keeps the noisy
// one as beauty_noisy. Frame N needs only surface.N.vdb, the scene and its [render] settings.
#pragma once

#include <functional>
#include <string>

#include "settings.h"

namespace mf::render {

struct RenderFrameResult {
  bool skipped = false;   // both images already there
  uint64_t rays = 0;
  double seconds = 0;     // tracing only
  double denoiseSeconds = 0;  // the denoiser (render.denoise)
  double setupSeconds = 0;  // reading, meshing, building the BVH
  size_t triangles = 0;
  double fluidCoverage = 0;  // fraction of pixels that show a fluid surface (PathTracer::coverage)
  bool anyFluid = false;     // a rendered phase had a surface at all
};

/// Renders frame `frame` of `scene` from `surfaceFile` into `exrPath` and `pngPath` (either may
/// be empty). Each phase in settings.phases must be a level set in the file, and the file
/// must pass its checksum; else a std::runtime_error naming the file. `progress(done, total)`
/// reports rows. With both paths empty nothing is traced: the result says only what the camera
/// sees (fluidCoverage).
RenderFrameResult renderFrame(const std::string& surfaceFile, const Scene& scene, const RenderSettings& settings,
                              const std::string& exrPath, const std::string& pngPath, int frame,
                              const std::function<void(int, int)>& progress = {});

}  // namespace mf::render
