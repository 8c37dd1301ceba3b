#include "fluid_interfaces.h"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <stdexcept>

#include "particle_surface.h"

namespace mf::surfacing {

namespace {

/// Whether fluid a's band meets another fluid's: a gap narrower than the two half widths.
bool touchesAnother(const std::vector<openvdb::FloatGrid::Ptr>& levelSets, size_t a) {
  if (!levelSets[a] || levelSets[a]->activeVoxelCount() == 0) return false;
  openvdb::MaskGrid others(false);
  for (size_t b = 0; b < levelSets.size(); ++b)
    if (b != a && levelSets[b]) others.tree().topologyUnion(levelSets[b]->tree());
  openvdb::MaskGrid both(false);
  both.tree().topologyUnion(levelSets[a]->tree());
  both.tree().topologyIntersection(others.tree());
  return both.tree().activeVoxelCount() > 0;
}

/// Central differences (in distance per voxel).
openvdb::Vec3f gradient(const openvdb::FloatGrid::ConstAccessor& acc, const openvdb::Coord& ijk) {
  openvdb::Vec3f g;
  for (int k = 0; k < 3; ++k) {
    openvdb::Coord lo = ijk, hi = ijk;
    --lo[k], ++hi[k];
    g[k] = 0.5f * (acc.getValue(hi) - acc.getValue(lo));
  }
  return g;
}

// The smallest |grad phi_a - grad phi_b| the split divides by: where the two surfaces face the
// same way, fluid a claims only where phi_a - phi_b is below a fifth of the overlap.
constexpr float kFlattestSplit = 0.2f;

}  // namespace

bool fluidBandsTouch(const std::vector<openvdb::FloatGrid::Ptr>& levelSets) {
  for (size_t a = 0; a < levelSets.size(); ++a)
    if (touchesAnother(levelSets, a)) return true;
  return false;
}

size_t closeFluidInterfaces(std::vector<openvdb::FloatGrid::Ptr>& levelSets, const openvdb::FloatGrid& united,
                            float overlap) {
  std::vector<size_t> fluids;
  for (size_t a = 0; a < levelSets.size(); ++a)
    if (levelSets[a] && levelSets[a]->activeVoxelCount() > 0) {
      if (levelSets[a]->transform() != united.transform())
        throw std::invalid_argument("closeFluidInterfaces: the level sets and the united one differ in transform");
      fluids.push_back(a);
    }
  if (fluids.size() < 2) return 0;
  std::atomic<size_t> flipped{0};
  std::vector<openvdb::FloatGrid::Ptr> closed(levelSets.size());
  for (size_t a : fluids) {
    if (!touchesAnother(levelSets, a)) continue;

    openvdb::FloatGrid::Ptr grid = levelSets[a]->deepCopy();
    const float halfWidth = grid->background();
    openvdb::tools::dilateActiveValues(grid->tree(), 1, openvdb::tools::NN_FACE, openvdb::tools::IGNORE_TILES);
    const float voxel = float(grid->voxelSize()[0]);
    openvdb::tree::LeafManager<openvdb::FloatTree>(grid->tree()).foreach([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
      std::vector<openvdb::FloatGrid::ConstAccessor> other;
      for (size_t b : fluids)
        if (b != a) other.push_back(levelSets[b]->getConstAccessor());
      auto own = levelSets[a]->getConstAccessor();
      auto all = united.getConstAccessor();
      size_t count = 0;
      for (auto v = leaf.beginValueOn(); v; ++v) {
        const float phi = *v;
        if (phi <= 0) continue;  // inside already: only a voxel outside can be claimed
        const openvdb::Coord ijk = v.getCoord();
        float nearest = std::numeric_limits<float>::max();
        size_t which = 0;
        for (size_t k = 0; k < other.size(); ++k)
          if (const float d = other[k].getValue(ijk); d < nearest) nearest = d, which = k;
        // Only within another fluid's band: elsewhere the united level set is this fluid's own
        // surface, made again, and its rounding must not move it.
        if (nearest >= halfWidth) continue;
        // Signed distance to the midway surface phi_a = phi_b: (phi_a - phi_b) / |grad phi_a -
        // grad phi_b|, which is (phi_a - phi_b) / 2 where the surfaces face each other across a
        // gap. Where they face the same way (a drop resting in a dent of another fluid, both
        // under the united surface) the difference barely changes across the gap, and the
        // unnormalised half difference would carry the overlap far into the other's side.
        const openvdb::Vec3f slope = gradient(own, ijk) - gradient(other[which], ijk);
        const float split = (phi - nearest) / std::max(slope.length() / voxel, kFlattestSplit);
        // The overlap tapers to nothing at the united surface: two fluids that both reached it
        // there would share its zero crossing, and coincident surfaces trap a renderer's rays.
        const float united = all.getValue(ijk);
        const float grown = std::max(united, split - std::min(overlap, std::max(0.0f, -united)));
        if (grown < phi) {
          count += phi > 0 && grown <= 0;
          v.setValue(grown);
        }
      }
      flipped += count;
    });
    trimBand(*grid, halfWidth);
    closed[a] = grid;
  }
  for (size_t a : fluids)
    if (closed[a]) levelSets[a] = closed[a];
  return flipped;
}

}  // namespace mf::surfacing
