#include "container_walls.h"

#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>

#include "sim/solids.h"

namespace mf::surfacing {

double containerDistance(const SolidSpec& c, const openvdb::Vec3d& p) {
  switch (c.shape) {
    case SolidSpec::Shape::Box: {
      double d = -1e300;
      for (int a = 0; a < 3; ++a) {
        d = std::max(d, c.min[a] - p[a]);
        if (a != 1 || !c.openTop) d = std::max(d, p[a] - c.max[a]);
      }
      return d;
    }
    case SolidSpec::Shape::Cylinder: {
      const double r = std::hypot(p.x() - c.base.x, p.z() - c.base.z);
      double d = std::max(r - c.radius, c.base.y - p.y());
      if (!c.openTop) d = std::max(d, p.y() - (c.base.y + c.height));
      return d;
    }
    case SolidSpec::Shape::Revolution: {
      const double y = p.y() - c.base.y;
      const double r = std::hypot(p.x() - c.base.x, p.z() - c.base.z);
      return std::max({r - profileRadius(c, y), c.profile.front().first - y, y - c.profile.back().first});
    }
  }
  return -1e300;
}

namespace {

/// phi = f(world position, phi) on every active voxel of the level set.
template <class F>
void remapActiveVoxels(openvdb::FloatGrid& grid, F&& f) {
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(grid.tree());
  const openvdb::math::Transform& xform = grid.transform();
  leaves.foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
    for (auto v = leaf.beginValueOn(); v; ++v) v.setValue(float(f(xform.indexToWorld(v.getCoord()), double(v.getValue()))));
  });
}

}  // namespace

void clipToSolids(openvdb::FloatGrid& grid, const std::vector<SolidSpec>& solids, double shell) {
  if (solids.empty()) return;
  remapActiveVoxels(grid, [&](const openvdb::Vec3d& p, double phi) {
    for (const SolidSpec& c : solids) {
      const double d = containerDistance(c, p);
      if (d > 0 && d < shell) phi = std::max(phi, d);
      else if (d <= 0 && d > -shell) phi = std::max(phi, d);  // inside, next to the wall
    }
    return phi;
  });
}

void wetContainerWalls(openvdb::FloatGrid& grid, const std::vector<SolidSpec>& solids, const std::vector<double>& depths) {
  if (solids.empty() || *std::max_element(depths.begin(), depths.end()) <= 0) return;
  remapActiveVoxels(grid, [&](const openvdb::Vec3d& p, double phi) {
    for (size_t k = 0; k < solids.size(); ++k) {
      const double depth = depths[k];
      if (depth <= 0) continue;
      const double w = std::abs(containerDistance(solids[k], p));
      if (w < depth) phi = std::min(phi, std::max(phi - depth, w - depth));
    }
    return phi;
  });
}

double wettingDepth(double voxelSize, double thickness) {
  // The bound keeps the liquid inside the glass that hides it: a coarse voxel reached through the
  // lamp's 6 mm wall by 17 mm, and the glasses' 4 mm by 1 mm, as streaks of water outside.
  return thickness > 0 ? std::min(2.0 * voxelSize, 0.75 * thickness) : 0.0;
}

}  // namespace mf::surfacing
