// One frame through the surfacing stage: particle file in, level sets (and what DCC tools need)
// out. Frame N depends only on particles.N.vdb, the scene and its [surfacing] settings, so frames can be spread over
// machines and re-run in any order.
#pragma once

#include <string>
#include <vector>

#include "settings.h"

namespace mf::surfacing {

struct SurfaceFrameResult {
  bool skipped = false;               // output already complete
  std::vector<std::string> written;   // files written
  size_t activeVoxels = 0;            // over all level sets
  size_t interfaceVoxels = 0;         // voxels a fluid gained in gaps to another (fluid_interfaces.h)
};

/// Reads `particleFile` (refused, naming it, if damaged or written by a scene with other phases
/// or spacing), surfaces the phases `settings` names and writes `surfaceFile`
/// (one FloatGrid level set per phase, named after it; optional "density" fog copies, "vel"
/// grids and "<attribute>_<phase>" attribute grids) and, when asked, meshes `meshDir/<phase>.NNNN.ply|obj`. Every file is written under a
/// temporary name and renamed; if `surfaceFile` exists (and every mesh asked for), nothing is
/// done.
SurfaceFrameResult surfaceFrame(const std::string& particleFile, const Scene& scene, const SurfacingSettings& settings,
                                const std::string& surfaceFile, const std::string& meshDir, int frame);

}  // namespace mf::surfacing
