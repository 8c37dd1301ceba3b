#include "particle_surface.h"

#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointRasterizeSDF.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/LevelSetTracker.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>

#include "bilateral_filter.h"
#include "sim/solids.h"

namespace mf::surfacing {

namespace {

openvdb::points::PointDataGrid::Ptr makePointGrid(const std::vector<openvdb::Vec3d>& positions,
                                                  const std::vector<openvdb::Vec3f>& velocities, double voxelSize) {
  using namespace openvdb::points;
  auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  PointAttributeVector<openvdb::Vec3d> wrapper(positions);
  auto index = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(wrapper, *transform);
  auto grid = createPointDataGrid<NullCodec, PointDataGrid>(*index, wrapper, *transform);
  if (!velocities.empty()) {
    appendAttribute<openvdb::Vec3f>(grid->tree(), "v");
    populateAttribute<PointDataTree, openvdb::tools::PointIndexTree, PointAttributeVector<openvdb::Vec3f>>(
        grid->tree(), index->tree(), "v", PointAttributeVector<openvdb::Vec3f>(velocities));
  }
  return grid;
}

/// Deactivates voxels at or beyond `halfWidth` from the surface (clamped to +-halfWidth), makes
/// that the background, and prunes: a narrow-band level set of exactly that half width.
void trimBand(openvdb::FloatGrid& grid, float halfWidth) {
  openvdb::tree::LeafManager<openvdb::FloatTree>(grid.tree()).foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
    for (auto v = leaf.beginValueOn(); v; ++v)
      if (std::fabs(*v) >= halfWidth) {
        v.setValue(*v > 0 ? halfWidth : -halfWidth);
        v.setValueOff();
      }
  });
  openvdb::tools::changeLevelSetBackground(grid.tree(), halfWidth);
  grid.setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::tools::pruneLevelSet(grid.tree());
}

}  // namespace

ParticleSurface particlesToSurface(const std::vector<openvdb::Vec3d>& positions,
                                   const std::vector<openvdb::Vec3f>& velocities, double spacing,
                                   const SurfacingSettings& s) {
  openvdb::initialize();
  const double voxel = s.voxelRatio * spacing;
  auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  ParticleSurface out;
  if (positions.empty()) {
    out.levelSet = openvdb::FloatGrid::create(float(kHalfWidthVoxels * voxel));
    out.levelSet->setTransform(transform);
    out.levelSet->setGridClass(openvdb::GRID_LEVEL_SET);
    return out;
  }
  // Points are binned at a coarser voxel (about one particle per voxel); the level set uses
  // its own transform.
  const auto points = makePointGrid(positions, velocities, spacing);
  const double band = kHalfWidthVoxels + s.filterRadius + 1;
  const double radius = s.radiusRatio * spacing, search = s.searchRatio * spacing;
  if (!velocities.empty()) {
    openvdb::GridPtrVec grids = openvdb::points::rasterizeSmoothSpheres<openvdb::points::PointDataGrid,
                                                                        openvdb::TypeList<openvdb::Vec3f>>(
        *points, radius, search, std::vector<std::string>{"v"}, band, transform);
    out.levelSet = openvdb::gridPtrCast<openvdb::FloatGrid>(grids.at(0));
    out.velocity = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids.at(1));
  } else {
    out.levelSet = openvdb::points::rasterizeSmoothSpheres(*points, radius, search, band, transform);
  }
  // Zhu & Bridson's field is a distance only near the surface: inside it saturates at -radius
  // and outside it stops about (search - radius) out. Make it a true distance in a band one
  // voxel wider than the filter's stencil (only values near the zero crossing shape the result):
  // widen the active band outwards, solve the eikonal equation on it (fast sweeping, which keeps
  // every voxel's sign; the mesh-based levelSetRebuild used before flooded enclosed cavities, so
  // bubbles inside a liquid vanished from its level set), trim; then filter and trim to 3 voxels.
  {
    const int wide = s.filterRadius + 1;
    // The raw field is active deep inside the fluid too; only `wide` voxels either side of the
    // crossing are needed: voxels not saturated at -radius, dilated by `wide`.
    openvdb::MaskGrid band(false);
    band.setTransform(out.levelSet->transform().copy());
    {
      auto mask = band.getAccessor();
      const float saturated = -0.99f * float(radius);
      for (auto v = out.levelSet->cbeginValueOn(); v; ++v)
        if (*v > saturated && v.isVoxelValue()) mask.setValueOn(v.getCoord());
    }
    openvdb::tools::dilateActiveValues(band.tree(), wide, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    out.levelSet->tree().topologyUnion(band.tree());
    out.levelSet->tree().topologyIntersection(band.tree());
    out.levelSet = openvdb::tools::sdfToSdf(*out.levelSet, 0.0f, 1);
    trimBand(*out.levelSet, float(wide * voxel));
  }
  bilateralFilter(*out.levelSet, s.filterRadius, s.filterSpatialSigma, s.filterRangeSigma, s.filterIterations);
  {
    // The filtered field is close to a distance already: a few reinitialisation sweeps and a
    // trim to 3 voxels cost less than meshing it again.
    openvdb::tools::LevelSetTracker<openvdb::FloatGrid> tracker(*out.levelSet);
    tracker.setNormCount(3);
    tracker.normalize();
    tracker.resize(int(kHalfWidthVoxels));
  }
  // The tracker's band ends on voxel topology, up to a voxel wider: trim to exactly 3 voxels.
  trimBand(*out.levelSet, float(kHalfWidthVoxels * voxel));
  return out;
}

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

void clipToSolids(openvdb::FloatGrid& grid, const std::vector<SolidSpec>& solids, double shell) {
  if (solids.empty()) return;
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(grid.tree());
  const openvdb::math::Transform& xform = grid.transform();
  leaves.foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
    for (auto v = leaf.beginValueOn(); v; ++v) {
      const openvdb::Vec3d p = xform.indexToWorld(v.getCoord());
      double phi = v.getValue();
      for (const SolidSpec& c : solids) {
        const double d = containerDistance(c, p);
        if (d > 0 && d < shell) phi = std::max(phi, d);
        else if (d <= 0 && d > -shell) phi = std::max(phi, d);  // inside, next to the wall
      }
      v.setValue(float(phi));
    }
  });
}

}  // namespace mf::surfacing
