#include "particle_surface.h"

#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointRasterizeSDF.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetTracker.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>

#include "bilateral_filter.h"
#include "bodies.h"
#include "redistance.h"

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

}  // namespace

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

namespace {

// ---------------------------------------------------------------------------------------------
// Bodies and colours.
//
// Zhu & Bridson's averaged position mixes every particle within the kernel radius (1.5
// spacings): between two droplets whose particles are closer than two kernel radii it falls in
// the empty gap, and the gap fills. The bilateral filter, a local average, then narrows what is
// left (a ridge of positive distance one voxel wide is averaged away). Both are right within
// one body of fluid and wrong across a gap, so both run per body, and the level set is the
// union (minimum) of the bodies' fields. A body is a connected part of the union of spheres of
// radius kLinkRatio / 2 spacings around the particles: particles closer than kLinkRatio
// spacings are linked. A body's particles stand about a spacing apart, linked many times over
// (a jitter of 0.3 spacings per axis leaves the test ball one body); across a gap of g voxels
// between two surfaces the nearest particles stand about 1.1 + g / 2 spacings apart (a surface
// lies about 0.56 spacings beyond its outer particles), so bodies stay apart down to a gap of
// about 0.8 voxels.
//
// Bounding the distance below by a union of spheres instead (phi = max(phi_ZB, phi_spheres))
// cannot do this: to leave a gap one voxel wide the spheres must be smaller than 0.56 spacings,
// and such spheres leave holes where a lattice is emptiest, at cube centres (0.87 spacings from
// the nearest particle) and face centres (0.71): the bound would pit every face and hollow the
// interior. What the spheres do tell, which particles belong together, is what is used here.
//
// Bodies far enough apart not to see each other (kernel and filter) share a colour: one pass
// of the pipeline per colour, usually one in all.

constexpr double kLinkRatio = 1.5;  // link length / particle spacing

// Bodies of fewer particles are not filtered. The filter (3-voxel stencil, 4 passes at the
// defaults) erodes a convex body by a voxel or so, and a small body is mostly edge: a compact
// cluster of n particles keeps, of its volume n s^3, 0 up to n = 20 (a bubble or a drop
// vanishes), 8 % at 30, 28 % at 50, 56 % at 80, 71 % at 120, 81 % at 200, 94 % at 500.
// Unfiltered, Zhu & Bridson's field holds 1.0-1.2 n s^3 at every n from 1 to 120
// (Surfacing.SmallBodiesKeepAboutTheirVolume).
constexpr uint32_t kUnfilteredBodyParticles = 100;

/// Zhu & Bridson's field of some particles, made a distance on a band `wide` voxels either side
/// of the surface, and bilateral-filtered.
openvdb::FloatGrid::Ptr filteredField(const std::vector<openvdb::Vec3d>& positions,
                                      const std::vector<openvdb::Vec3f>& velocities, double spacing,
                                      const SurfacingSettings& s, const openvdb::math::Transform::Ptr& transform,
                                      openvdb::Vec3SGrid::Ptr& velocity) {
  const double voxel = transform->voxelSize()[0];
  const double band = kHalfWidthVoxels + s.filterRadius + 1;
  const double radius = s.radiusRatio * spacing, search = s.searchRatio * spacing;
  const int wide = s.filterRadius + 1;
  openvdb::FloatGrid::Ptr field;
  {
    // Points are binned at a coarser voxel (about one particle per voxel); the level set uses
    // its own transform. The point grid is freed before the band is solved.
    const auto points = makePointGrid(positions, velocities, spacing);
    if (!velocities.empty()) {
      openvdb::GridPtrVec grids = openvdb::points::rasterizeSmoothSpheres<openvdb::points::PointDataGrid,
                                                                          openvdb::TypeList<openvdb::Vec3f>>(
          *points, radius, search, std::vector<std::string>{"v"}, band, transform);
      field = openvdb::gridPtrCast<openvdb::FloatGrid>(grids.at(0));
      velocity = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids.at(1));
    } else {
      field = openvdb::points::rasterizeSmoothSpheres(*points, radius, search, band, transform);
    }
  }
  // Zhu & Bridson's field is a distance only near the surface: inside it saturates at -radius
  // and outside it stops about (search - radius) out. Make it a true distance in a band one
  // voxel wider than the filter's stencil (only values near the zero crossing shape the result):
  // select the band, solve the eikonal equation on it (redistance, which keeps every voxel's
  // sign; the mesh-based levelSetRebuild used before flooded enclosed cavities, so bubbles
  // inside a liquid vanished from its level set), trim; then filter.
  {
    // The raw field is active deep inside the fluid too; only `wide` voxels either side of the
    // zero crossing are needed: the voxels with a face neighbour of the other sign, dilated to
    // every voxel within `wide` of one (a cube of half `wide` plus an octahedron of the rest
    // holds the ball of radius `wide`; around small droplets it has a quarter fewer voxels than
    // the cube of `wide`). Selecting "not saturated at -radius" instead took the whole interior
    // wherever the particles are not a perfect lattice: 10.6 M voxels to solve for instead of
    // 3.7 M at 1 M particles, for the same result.
    openvdb::MaskGrid mask(false);
    mask.tree().topologyUnion(field->tree());
    openvdb::tree::LeafManager<openvdb::MaskTree>(mask.tree()).foreach([&](openvdb::MaskTree::LeafNodeType& leaf, size_t) {
      openvdb::tree::ValueAccessor<const openvdb::FloatTree> acc(field->tree());
      for (auto v = leaf.getValueMask().beginOn(); v; ++v) {
        const openvdb::Coord ijk = leaf.offsetToGlobalCoord(v.pos());
        const bool inside = acc.getValue(ijk) < 0;
        bool crossing = false;
        for (int a = 0; a < 3 && !crossing; ++a)
          for (int d = -1; d <= 1 && !crossing; d += 2) {
            openvdb::Coord n = ijk;
            n[a] += d;
            crossing = (acc.getValue(n) < 0) != inside;
          }
        if (!crossing) leaf.setActiveState(v.pos(), false);
      }
    });
    openvdb::tools::dilateActiveValues(mask.tree(), (wide + 1) / 2, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    openvdb::tools::dilateActiveValues(mask.tree(), wide / 2, openvdb::tools::NN_FACE, openvdb::tools::IGNORE_TILES);
    field->tree().topologyUnion(mask.tree());
    field->tree().topologyIntersection(mask.tree());
    // The interior's leaves, now inactive, become tiles of their sign.
    openvdb::tools::pruneLevelSet(field->tree());
  }
  redistance(*field, float(wide * voxel));
  trimBand(*field, float(wide * voxel));
  bilateralFilter(*field, s.filterRadius, s.filterSpatialSigma, s.filterRangeSigma, s.filterIterations);
  return field;
}

/// Unites `field` (and its velocity grid) into `out`: where both have a velocity, the one whose
/// surface is nearer.
void unite(ParticleSurface& out, const openvdb::FloatGrid::Ptr& field, const openvdb::Vec3SGrid::Ptr& vel) {
  if (!out.levelSet) {
    out.levelSet = field;
    out.velocity = vel;
    return;
  }
  if (vel && out.velocity) {
    auto a = out.levelSet->getConstAccessor(), b = field->getConstAccessor();
    auto dst = out.velocity->getAccessor();
    for (auto it = vel->cbeginValueOn(); it; ++it) {
      if (!it.isVoxelValue()) continue;
      const openvdb::Coord ijk = it.getCoord();
      if (!dst.isValueOn(ijk) || b.getValue(ijk) < a.getValue(ijk)) dst.setValue(ijk, *it);
    }
  }
  openvdb::tools::csgUnion(*out.levelSet, *field);
}

}  // namespace

namespace {

/// The union of the bodies among `positions` (body[i] numbers them 0..bodies-1 as findBodies
/// does), each surfaced as if alone (before the final renormalisation); null when there are no
/// positions.
ParticleSurface surfaceBodies(const std::vector<openvdb::Vec3d>& positions, const std::vector<openvdb::Vec3f>& velocities,
                              const std::vector<uint32_t>& body, uint32_t bodies, double spacing, const SurfacingSettings& s,
                              const openvdb::math::Transform::Ptr& transform) {
  ParticleSurface out;
  if (positions.empty()) return out;
  const double voxel = transform->voxelSize()[0];
  std::vector<uint32_t> colour;
  // Bodies of one colour are surfaced exactly as if alone when no kernel holds particles of
  // both (2 search radii) and their bands (`wide` voxels beyond surfaces about a particle radius
  // out) stay more than a stencil radius apart. Several colours: each pass surfaces its bodies,
  // and the level set is the union of the passes, renormalised together.
  const double near = std::max(2 * s.searchRatio * spacing,
                               2 * s.radiusRatio * spacing + (2 * (s.filterRadius + 1) + s.filterRadius + 1) * voxel);
  const uint32_t colours = colourBodies(positions, body, bodies, near, colour);
  if (colours == 1) {
    out.levelSet = filteredField(positions, velocities, spacing, s, transform, out.velocity);
    return out;
  }
  for (uint32_t c = 0; c < colours; ++c) {
    std::vector<openvdb::Vec3d> p;
    std::vector<openvdb::Vec3f> v;
    for (size_t i = 0; i < positions.size(); ++i)
      if (colour[body[i]] == c) {
        p.push_back(positions[i]);
        if (!velocities.empty()) v.push_back(velocities[i]);
      }
    openvdb::Vec3SGrid::Ptr vel;
    auto field = filteredField(p, v, spacing, s, transform, vel);
    unite(out, field, vel);
  }
  return out;
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
  // Small bodies (bubbles, drops) skip the filter, which would shrink them away: see
  // kUnfilteredBodyParticles. The two sets are surfaced apart and united.
  std::vector<uint32_t> body;
  const uint32_t bodies = findBodies(positions, kLinkRatio * spacing, body);
  std::vector<uint32_t> size(bodies, 0);
  for (uint32_t b : body) ++size[b];
  // Each set keeps its bodies' labels, renumbered in order of first appearance: the numbering
  // findBodies gives the set's own particles, so the bodies are not searched for again.
  struct Subset {
    std::vector<openvdb::Vec3d> p;
    std::vector<openvdb::Vec3f> v;
    std::vector<uint32_t> body;
    uint32_t bodies = 0;
  } large, small;
  std::vector<uint32_t> renumbered(bodies, ~0u);
  for (size_t i = 0; i < positions.size(); ++i) {
    Subset& set = size[body[i]] < kUnfilteredBodyParticles ? small : large;
    uint32_t& label = renumbered[body[i]];
    if (label == ~0u) label = set.bodies++;
    set.p.push_back(positions[i]);
    set.body.push_back(label);
    if (!velocities.empty()) set.v.push_back(velocities[i]);
  }
  SurfacingSettings unfiltered = s;
  unfiltered.filterIterations = 0;
  out = surfaceBodies(large.p, large.v, large.body, large.bodies, spacing, s, transform);
  ParticleSurface smallSurface = surfaceBodies(small.p, small.v, small.body, small.bodies, spacing, unfiltered, transform);
  if (smallSurface.levelSet) unite(out, smallSurface.levelSet, smallSurface.velocity);
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

}  // namespace mf::surfacing
