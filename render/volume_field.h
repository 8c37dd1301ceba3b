// A scalar field inside a fluid (surfacing's attribute grid, e.g. temperature_<fluid>) as a dense
// box of voxels for the path tracer's colour ramps: trilinear between voxel centres, clamped to
// the box. Dense, because the fields are small (the fluid's box at the level set's voxel size)
// and a lookup is then a few loads, with no tree walk and no per-thread accessor.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <openvdb/openvdb.h>

#include "sim/vec3.h"

namespace mf::render {

class VolumeField {
 public:
  /// The grid's active voxels' bounding box, its inactive voxels at the background value.
  /// Throws std::runtime_error unless the grid has uniform voxels without rotation.
  explicit VolumeField(const openvdb::FloatGrid& grid);

  Real voxelSize() const { return voxel_; }

  Real at(const Vec3& p) const {
    if (values_.empty()) return 0;
    int i0[3], i1[3];
    Real f[3];
    for (int a = 0; a < 3; ++a) {
      const Real x = std::clamp((p[a] - origin_[a]) / voxel_, Real(0), Real(n_[a] - 1));
      i0[a] = std::min(int(x), n_[a] - 1), i1[a] = std::min(i0[a] + 1, n_[a] - 1), f[a] = x - i0[a];
    }
    auto val = [&](int i, int j, int k) { return Real(values_[(size_t(k) * n_[1] + j) * n_[0] + i]); };
    auto lerpX = [&](int j, int k) { return val(i0[0], j, k) * (1 - f[0]) + val(i1[0], j, k) * f[0]; };
    auto lerpY = [&](int k) { return lerpX(i0[1], k) * (1 - f[1]) + lerpX(i1[1], k) * f[1]; };
    return lerpY(i0[2]) * (1 - f[2]) + lerpY(i1[2]) * f[2];
  }

 private:
  Vec3 origin_;  // world position of voxel (0, 0, 0)'s centre
  Real voxel_ = 1;
  int n_[3] = {0, 0, 0};
  std::vector<float> values_;  // x fastest
};

}  // namespace mf::render
