#include "attribute_grid.h"

#include <cmath>

namespace mf::surfacing {

openvdb::FloatGrid::Ptr attributeGrid(const std::vector<openvdb::Vec3d>& positions, const std::vector<float>& values,
                                      double radius, const openvdb::math::Transform& transform) {
  auto num = openvdb::DoubleGrid::create(0.0), den = openvdb::DoubleGrid::create(0.0);
  auto a = num->getAccessor(), b = den->getAccessor();
  const double r2 = radius * radius;
  for (size_t i = 0; i < positions.size(); ++i) {
    const openvdb::Vec3d& p = positions[i];
    const openvdb::Vec3d lo = transform.worldToIndex(p - openvdb::Vec3d(radius)), hi = transform.worldToIndex(p + openvdb::Vec3d(radius));
    openvdb::Coord c;
    for (c.x() = int(std::ceil(lo.x())); c.x() <= int(std::floor(hi.x())); ++c.x())
      for (c.y() = int(std::ceil(lo.y())); c.y() <= int(std::floor(hi.y())); ++c.y())
        for (c.z() = int(std::ceil(lo.z())); c.z() <= int(std::floor(hi.z())); ++c.z()) {
          const double d2 = (transform.indexToWorld(c) - p).lengthSqr();
          if (d2 >= r2) continue;
          const double q = 1 - d2 / r2, w = q * q * q;
          a.setValue(c, a.getValue(c) + w * values[i]);
          b.setValue(c, b.getValue(c) + w);
        }
  }
  auto out = openvdb::FloatGrid::create(0.0f);
  out->setTransform(transform.copy());
  auto o = out->getAccessor();
  for (auto it = den->cbeginValueOn(); it; ++it) o.setValue(it.getCoord(), float(a.getValue(it.getCoord()) / *it));
  return out;
}

}  // namespace mf::surfacing
