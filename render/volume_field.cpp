#include "volume_field.h"

#include <stdexcept>

namespace mf::render {

VolumeField::VolumeField(const openvdb::FloatGrid& grid) {
  const openvdb::math::Transform& xf = grid.transform();
  const bool axisAligned = xf.baseMap()->isType<openvdb::math::UniformScaleTranslateMap>() ||
                           xf.baseMap()->isType<openvdb::math::UniformScaleMap>();
  if (!grid.hasUniformVoxels() || !xf.isLinear() || !axisAligned)
    throw std::runtime_error("grid \"" + grid.getName() + "\" has no uniform, axis-aligned voxels");
  voxel_ = grid.voxelSize()[0];
  const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
  if (box.empty()) return;
  const openvdb::Vec3d o = xf.indexToWorld(box.min());
  origin_ = {o.x(), o.y(), o.z()};
  const openvdb::Coord d = box.dim();
  n_[0] = d.x(), n_[1] = d.y(), n_[2] = d.z();
  values_.resize(size_t(n_[0]) * n_[1] * n_[2]);
  auto acc = grid.getConstAccessor();
  size_t idx = 0;
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) values_[idx++] = acc.getValue(box.min().offsetBy(i, j, k));
}

}  // namespace mf::render
