// Fitting a fluid's level set to its containers' walls: cut where the particles' surface bulges
// through a wall, and extended into a wall the render draws, so that liquid meets glass with no
// film of air between them. Grids in, grids out; the walls are the scene's solids.
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

#include "sim/scene.h"

namespace mf::surfacing {

/// Signed distance to a container's interior (negative inside; exact for boxes and cylinders,
/// a close bound for surfaces of revolution).
double containerDistance(const SolidSpec& solid, const openvdb::Vec3d& p);

/// @brief Cuts the level set where it reaches through a container wall: outside each container,
/// within `shell` of its surface, the distance becomes max(phi, distance to the container's
/// interior). Fluid inside a container thus ends at the wall, not a particle radius beyond it.
void clipToSolids(openvdb::FloatGrid& levelSet, const std::vector<SolidSpec>& solids, double shell);

/// @brief Liquid that stops short of a container wall (a gap of up to `depth`, which a renderer
/// shows as a film of air) is extended through the gap and `depth` into the wall, where the
/// glass hides it: phi = min(phi, max(phi - depth, |w| - depth)), w the distance to the wall.
/// Away from walls nothing changes; at the wall the free surface rises by at most `depth`, like
/// a meniscus. One depth per solid (0: none), less than its wall's thickness, or the liquid
/// shows as a film outside the glass.
void wetContainerWalls(openvdb::FloatGrid& levelSet, const std::vector<SolidSpec>& solids, const std::vector<double>& depths);

/// The depth wetContainerWalls uses for a wall drawn `thickness` thick (0: not drawn): two
/// voxels (about a particle radius at the default voxel size), at most 3/4 of the thickness.
double wettingDepth(double voxelSize, double thickness);

}  // namespace mf::surfacing
