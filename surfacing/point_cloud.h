// Particles as a PLY point cloud, for DCC tools that do not read OpenVDB points (Blender imports
// PLY vertices): one vertex per particle with its attributes as vertex properties.
#pragma once

#include <string>

#include "sim/particle_io.h"

namespace mf::surfacing {

/// Writes `path` (binary little-endian PLY, atomically): float x y z, float vx vy vz, double id
/// (exact to 2^53), int phase, float pscale, then every scalar attribute of the frame as a float
/// property of its name (density, pressure, temperature, ...), in name order.
void writePointCloudPly(const std::string& path, const ParticleFrame& frame);

}  // namespace mf::surfacing
