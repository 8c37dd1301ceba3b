// A particle attribute (temperature, dye) as a grid beside a fluid's level set, for the
// renderer's colour ramps and for DCC tools: the Shepard-normalised kernel average
//   A(x) = sum_j w(|x - x_j|) A_j / sum_j w(|x - x_j|),  w(r) = (1 - r^2/R^2)^3 for r < R,
// on every voxel within R of a particle. It reproduces a constant field exactly and a linear one
// inside a uniform lattice; R = 2 spacings covers the level set's inside, which lies within
// search_ratio (1.5) spacings of a particle.
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

namespace mf::surfacing {

/// @brief The attribute `values` of the particles at `positions` on the voxels of `transform`
/// within `radius` of a particle (active there; background 0). Serial in particle order, so the
/// bits do not depend on the thread count.
openvdb::FloatGrid::Ptr attributeGrid(const std::vector<openvdb::Vec3d>& positions, const std::vector<float>& values,
                                      double radius, const openvdb::math::Transform& transform);

}  // namespace mf::surfacing
