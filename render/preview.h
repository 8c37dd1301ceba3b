// A quick look at a simulation without surfacing: particles as lit spheres, coloured by phase
// or by temperature, drawn off-screen with OSMesa (software OpenGL) straight from a particle
// file. Seconds per frame; for checking a simulation, not for final images.
#pragma once

#include <string>

#include "settings.h"

namespace mf::render {

enum class PreviewColour { Phase, Temperature };

struct PreviewResult {
  bool skipped = false;
  size_t particles = 0;
  double seconds = 0;
};

/// Draws `particleFile` with the scene's render camera into `pngPath` (skipped if it exists). The
/// file is refused, naming it, if damaged or written by a scene with other phases or spacing.
/// Temperature colours run blue (coldest) to red (hottest) over [tMin, tMax] deg C.
PreviewResult renderPreview(const std::string& particleFile, const Scene& scene, const RenderSettings& settings, const std::string& pngPath,
                            PreviewColour colour = PreviewColour::Phase, double tMin = 0, double tMax = 100);

}  // namespace mf::render
