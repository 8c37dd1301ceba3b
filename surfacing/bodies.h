// Connected bodies of one fluid's particles, and colours that let bodies far enough apart share
// a pass of the surfacing pipeline (particle_surface.cpp explains why it surfaces per body).
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace mf::surfacing {

/// @brief Connected parts of a fluid: particles closer than `link` belong to one body
/// (particlesToSurface links particles closer than 1.5 spacings and surfaces each body as if
/// alone). Returns the number of bodies; body[i] numbers them 0.. in order of each body's lowest
/// particle index. The same on any thread count.
uint32_t findBodies(const std::vector<openvdb::Vec3d>& positions, double link, std::vector<uint32_t>& body);

/// @brief Colour of each body: bodies with particles closer than `near` get different colours;
/// greedy, largest body first. Returns the number of colours.
uint32_t colourBodies(const std::vector<openvdb::Vec3d>& p, const std::vector<uint32_t>& body, uint32_t bodies,
                      double near, std::vector<uint32_t>& colour);

}  // namespace mf::surfacing
