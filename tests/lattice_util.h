// Jittered lattices of particles for the surfacing tests.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace mf::test {

/// Particles at the centres of the cells of `spacing` that fill [lo, hi), each moved by up to
/// `jitter` spacings along each axis (uniform, from `seed`); with `inside`, only where it holds.
inline std::vector<openvdb::Vec3d> lattice(const openvdb::Vec3d& lo, const openvdb::Vec3d& hi, double spacing,
                                           double jitter, uint32_t seed,
                                           const std::function<bool(const openvdb::Vec3d&)>& inside = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter * spacing, jitter * spacing);
  std::vector<openvdb::Vec3d> out;
  for (double z = lo.z() + 0.5 * spacing; z < hi.z(); z += spacing)
    for (double y = lo.y() + 0.5 * spacing; y < hi.y(); y += spacing)
      for (double x = lo.x() + 0.5 * spacing; x < hi.x(); x += spacing) {
        const openvdb::Vec3d p(x, y, z);
        if (inside && !inside(p)) continue;
        out.push_back(p + openvdb::Vec3d(u(rng), u(rng), u(rng)));
      }
  return out;
}

}  // namespace mf::test
