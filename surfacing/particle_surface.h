// Particles of one fluid to a narrow-band level set: per connected body of particles, Zhu &
// Bridson (2005) averaged-position distance (OpenVDB's points::rasterizeSmoothSpheres) and a
// bilateral filter on the distance (bilateral_filter.h); the bodies' union, renormalised to a
// true distance with a 3-voxel half width (container_walls.h fits it to the walls).
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

#include "settings.h"

namespace mf::surfacing {

constexpr double kHalfWidthVoxels = 3.0;

struct ParticleSurface {
  openvdb::FloatGrid::Ptr levelSet;  // GRID_LEVEL_SET, half width 3 voxels, background 3 voxels
  openvdb::Vec3SGrid::Ptr velocity;  // closest-particle velocity on the level set's voxels, or null
};

/// @brief Level set of one fluid's particles.
/// @param positions        world-space particle positions (m)
/// @param velocities       their velocities, or empty for no velocity grid
/// @param particleSpacing  the simulation's particle spacing (m): all sizes are relative to it
/// @param settings         voxel size, kernel radii and filter widths (scene [surfacing])
ParticleSurface particlesToSurface(const std::vector<openvdb::Vec3d>& positions,
                                   const std::vector<openvdb::Vec3f>& velocities, double particleSpacing,
                                   const SurfacingSettings& settings);

/// Deactivates voxels at or beyond `halfWidth` from the surface (clamped to +-halfWidth), makes
/// that the background, and prunes: a narrow-band level set of exactly that half width.
void trimBand(openvdb::FloatGrid& grid, float halfWidth);

}  // namespace mf::surfacing
