// Surfaces of periodic scenes (scene.periodic). The simulation's fluid continues through a
// periodic face; a level set built from the particles alone would round off there. Images of
// the particles near each face, one period across, make the surface near the face what the
// wrapped fluid gives, and the level set is then cut flat at the faces, so that copies of a
// frame placed a period apart meet without a seam.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

#include "sim/periodic.h"

namespace mf::surfacing {

/// @brief Images of the points within `margin` of a periodic face, shifted one period across
/// (a point near an edge or corner gets one per combination of its faces).
/// @return for each image, the index of its source point; the image positions go to `images`
std::vector<uint32_t> periodicImages(const std::vector<openvdb::Vec3d>& positions, const PeriodicDomain& domain,
                                     double margin, std::vector<openvdb::Vec3d>& images);

/// @brief Intersects the level set with the domain's slab on the periodic axes (CSG with a
/// box level set): the surface ends flat at the periodic faces. No-op without periodic axes.
void cutAtPeriodicFaces(openvdb::FloatGrid& levelSet, const PeriodicDomain& domain);

}  // namespace mf::surfacing
