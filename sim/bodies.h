// Bodies of fluid: connected sets of particles of one phase, two particles linked when they are
// within a link distance (issue 23 measures scenes this way, at 1.5 spacings). A lava lamp's wax
// pool and the blobs that leave it, a glass's bubbles, an oil layer's droplets are each a body.
//
// Deterministic: the labels depend only on the positions and phases, never on the number of
// threads; bodies are numbered by phase, then size (largest first), then smallest particle index.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vec3.h"

namespace mf {

struct FluidBody {
  int32_t phase = 0;
  std::vector<uint32_t> members;  // particle indices, ascending
  Vec3 centroid, lower, upper;    // mean position and bounding box
  /// sqrt(smallest / largest eigenvalue of the members' position covariance): 1 for a ball (or
  /// a cube), 0 for a sheet or a line; 1 for bodies of fewer than 4 particles.
  Real roundness = 1;
  size_t size() const { return members.size(); }
};

struct FluidBodies {
  std::vector<int32_t> bodyOf;  // per particle: its body's index in `bodies`
  std::vector<FluidBody> bodies;
};

/// Labels the bodies of n particles (positions x, phases phase) linked within `linkDistance`.
FluidBodies findBodies(const Vec3* x, const int32_t* phase, size_t n, Real linkDistance);

}  // namespace mf
