#include "periodic_images.h"

#include <openvdb/tools/Composite.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>

namespace mf::surfacing {

std::vector<uint32_t> periodicImages(const std::vector<openvdb::Vec3d>& positions, const PeriodicDomain& domain,
                                     double margin, std::vector<openvdb::Vec3d>& images) {
  std::vector<uint32_t> source;
  images.clear();
  if (!domain.any()) return source;
  // At most half a period from a face: then a point is near one face of each axis only.
  const Vec3 m(std::min(margin, 0.5 * domain.length.x), std::min(margin, 0.5 * domain.length.y),
               std::min(margin, 0.5 * domain.length.z));
  for (size_t i = 0; i < positions.size(); ++i) {
    const Vec3 p(positions[i].x(), positions[i].y(), positions[i].z());
    domain.forEachImage(p, p, m, [&](const Vec3& shift) {
      images.push_back(positions[i] + openvdb::Vec3d(shift.x, shift.y, shift.z));
      source.push_back(uint32_t(i));
    });
  }
  return source;
}

void cutAtPeriodicFaces(openvdb::FloatGrid& levelSet, const PeriodicDomain& domain) {
  if (!domain.any() || levelSet.activeVoxelCount() == 0) return;
  // On the other axes the box reaches well past the level set, so it cuts nothing there.
  const openvdb::math::Transform& xform = levelSet.transform();
  const openvdb::CoordBBox active = levelSet.evalActiveVoxelBoundingBox();
  const double pad = 8 * xform.voxelSize()[0];
  openvdb::Vec3d lo = xform.indexToWorld(active.min()), hi = xform.indexToWorld(active.max());
  for (int a = 0; a < 3; ++a) {
    if (domain.wraps(a)) {
      lo[a] = domain.lo[a];
      hi[a] = domain.lo[a] + domain.length[a];
    } else {
      lo[a] -= pad;
      hi[a] += pad;
    }
  }
  const float halfWidth = float(levelSet.background() / xform.voxelSize()[0]);
  openvdb::FloatGrid::Ptr box =
      openvdb::tools::createLevelSetBox<openvdb::FloatGrid>(openvdb::math::BBox<openvdb::Vec3d>(lo, hi), xform, halfWidth);
  openvdb::tools::csgIntersection(levelSet, *box);
}

}  // namespace mf::surfacing
