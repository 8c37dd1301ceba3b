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
  for (size_t i = 0; i < positions.size(); ++i) {
    const openvdb::Vec3d& p = positions[i];
    // Per axis the shifts that apply: 0, and +L near the lower face or -L near the upper one.
    double shift[3][2];
    int count[3];
    for (int a = 0; a < 3; ++a) {
      shift[a][0] = 0;
      count[a] = 1;
      if (!domain.wraps(a)) continue;
      const double lo = domain.lo[a], L = domain.length[a], m = std::min(margin, 0.5 * L);
      if (p[a] - lo < m) shift[a][count[a]++] = L;
      else if (lo + L - p[a] < m) shift[a][count[a]++] = -L;
    }
    for (int iz = 0; iz < count[2]; ++iz)
      for (int iy = 0; iy < count[1]; ++iy)
        for (int ix = 0; ix < count[0]; ++ix) {
          if (ix == 0 && iy == 0 && iz == 0) continue;
          images.push_back(p + openvdb::Vec3d(shift[0][ix], shift[1][iy], shift[2][iz]));
          source.push_back(uint32_t(i));
        }
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
