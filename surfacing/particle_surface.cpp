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
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "bilateral_filter.h"
#include "sim/disjoint_sets.h"
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

/// Signed distance to the zero crossing on the active voxels of `grid` (a band around it), as
/// tools::sdfToSdf computes it: the voxels next to the crossing get its distance along the axes,
/// the others the Godunov upwind solution of |grad phi| = 1 (FastSweeping's update, in the same
/// float arithmetic). Instead of FastSweeping's eight diagonal sweeps, whose bookkeeping (a copy
/// of the band, and masks per leaf and diagonal slice for four directions) cost most of the
/// stage's memory at 1 M particles, the update runs in Jacobi passes over the voxels next to
/// those that changed in the pass before, until none changes: per leaf, in parallel, with a
/// result independent of the thread count. The same values as sdfToSdf to 1e-6 voxels on the
/// tests' shapes. Distances from `limit` up are not needed (the band is trimmed there): the
/// voxels beyond it keep +-FLT_MAX or a value at least `limit`, which cannot change the voxels
/// below it (an update reads only smaller neighbours).
void redistance(openvdb::FloatGrid& grid, float limit) {
  using TreeT = openvdb::FloatTree;
  using LeafT = TreeT::LeafNodeType;
  using Mask = LeafT::NodeMaskType;
  constexpr int kDim = int(LeafT::DIM);
  const float h = float(grid.voxelSize()[0]), sqrt2h = std::sqrt(2.0f) * h, big = std::numeric_limits<float>::max();
  TreeT& tree = grid.tree();
  static const openvdb::Coord kNeighbour[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  openvdb::tree::LeafManager<TreeT> leaves(tree, 1);
  const size_t count = leaves.leafCount();
  std::vector<Mask> fixed(count);  // the voxels next to the crossing
  // Initial values (into the auxiliary buffers, then swapped in).
  leaves.foreach([&](LeafT& leaf, size_t n) {
    openvdb::tree::ValueAccessor<const TreeT> acc(tree);
    float* out = leaves.getBuffer(n, 1).data();
    for (auto v = leaf.cbeginValueAll(); v; ++v) {
      const float value = *v;
      const bool above = value > 0;
      out[v.pos()] = above ? big : -big;
      if (!v.isValueOn()) continue;
      const openvdb::Coord ijk = v.getCoord();
      const bool less = value < 0;
      float nb[6];
      bool cross[6], any = false;
      for (int i = 0; i < 6; ++i) {
        nb[i] = acc.getValue(ijk + kNeighbour[i]);
        cross[i] = less != (nb[i] < 0);
        any |= cross[i];
      }
      if (!any) continue;
      fixed[n].setOn(v.pos());
      if (openvdb::math::isApproxZero(value)) {
        out[v.pos()] = 0;
        continue;
      }
      float sum = 0;
      for (int a = 0; a < 3; ++a) {
        float d = big;
        if (cross[2 * a]) d = std::fabs(value / (value - nb[2 * a]));
        if (cross[2 * a + 1]) d = std::min(d, std::fabs(value / (value - nb[2 * a + 1])));
        if (d < big) sum += 1 / (d * d);
      }
      out[v.pos()] = above ? h / std::sqrt(sum) : -h / std::sqrt(sum);
    }
  });
  leaves.swapLeafBuffer(1);
  leaves.removeAuxBuffers();
  // Each leaf's six face neighbours (-1: none, where tiles and background carry no distance).
  std::vector<std::array<long, 6>> next(count);
  {
    std::unordered_map<const LeafT*, long> index;
    for (size_t n = 0; n < count; ++n) index[&leaves.leaf(n)] = long(n);
    leaves.foreach([&](LeafT& leaf, size_t n) {
      openvdb::tree::ValueAccessor<const TreeT> acc(tree);
      for (int i = 0; i < 6; ++i) {
        const openvdb::Coord& d = kNeighbour[i];
        const LeafT* other = acc.probeConstLeaf(leaf.origin() + openvdb::Coord(d.x() * kDim, d.y() * kDim, d.z() * kDim));
        next[n][size_t(i)] = other ? index.at(other) : -1;
      }
    });
  }
  struct Near {  // a neighbour's distance, as FastSweeping's NN
    float v;
    bool operator<(const Near& o) const { return v < o.v; }
    explicit operator bool() const { return v < 1000.0f; }
  };
  std::vector<Mask> changed = fixed, changedNext(count);
  std::vector<char> leafChanged(count), leafChangedNext(count);
  for (size_t n = 0; n < count; ++n) leafChanged[n] = !fixed[n].isOff();
  std::vector<float*> data(count);
  for (size_t n = 0; n < count; ++n) data[n] = leaves.leaf(n).buffer().data();
  std::vector<std::vector<std::pair<openvdb::Index, float>>> updates(count);
  for (bool any = true; any;) {
    // New values of the voxels next to a change, from the values before this pass.
    leaves.foreach([&](LeafT& leaf, size_t n) {
      bool near = leafChanged[n];
      for (long o : next[n]) near |= o >= 0 && leafChanged[size_t(o)];
      if (!near) return;
      const float* in = data[n];
      for (auto v = leaf.getValueMask().beginOn(); v; ++v) {
        const openvdb::Index pos = v.pos();
        if (fixed[n].isOn(pos)) continue;
        const openvdb::Coord local = LeafT::offsetToLocalCoord(pos);
        // Each neighbour's leaf (-1: none) and offset in it.
        long leafOf[6];
        openvdb::Index at[6];
        bool moved = false;
        for (int i = 0; i < 6; ++i) {
          openvdb::Coord q = local + kNeighbour[i];
          const int a = i / 2;
          leafOf[i] = long(n);
          if (q[a] < 0 || q[a] >= kDim) {
            leafOf[i] = next[n][size_t(i)];
            q[a] = (q[a] + kDim) % kDim;
          }
          at[i] = LeafT::coordToOffset(q);
          moved |= leafOf[i] >= 0 && changed[size_t(leafOf[i])].isOn(at[i]);
        }
        if (!moved) continue;
        Near d[6];
        for (int i = 0; i < 6; ++i) d[i] = Near{leafOf[i] < 0 ? big : std::fabs(data[size_t(leafOf[i])][at[i]])};
        Near d1 = std::min(d[0], d[1]), d2 = std::min(d[2], d[3]), d3 = std::min(d[4], d[5]);
        if (!(d1 || d2 || d3)) continue;
        const float value = in[pos], sign = value >= 0 ? 1.0f : -1.0f, absV = std::fabs(value);
        if (d2 < d1) std::swap(d1, d2);
        if (d3 < d2) std::swap(d2, d3);
        if (d2 < d1) std::swap(d1, d2);
        float update = d1.v + h;
        if (update > d2.v) {
          update = big;
          if (d2.v <= sqrt2h + d1.v) {
            const float D = 2.0f * h * h - (d1.v - d2.v) * (d1.v - d2.v);
            const float two = 0.5f * (d1.v + d2.v + std::sqrt(D));
            if (two > d2.v && two <= d3.v) update = two;
          }
          if (update == big) {
            const float d123 = d1.v + d2.v + d3.v;
            const float D = d123 * d123 - 3.0f * (d1.v * d1.v + d2.v * d2.v + d3.v * d3.v - h * h);
            if (D >= 0) update = float(1.0 / 3.0) * (d123 + std::sqrt(D));
          }
        }
        if (update < absV && update < limit) updates[n].emplace_back(pos, sign * update);
      }
    });
    // Apply them.
    std::atomic<bool> anyChange{false};
    leaves.foreach([&](LeafT&, size_t n) {
      changedNext[n].setOff();
      for (const auto& [pos, value] : updates[n]) {
        data[n][pos] = value;
        changedNext[n].setOn(pos);
      }
      leafChangedNext[n] = !updates[n].empty();
      if (!updates[n].empty()) anyChange = true;
      updates[n].clear();
    });
    std::swap(changed, changedNext);
    std::swap(leafChanged, leafChangedNext);
    any = anyChange;
  }
}

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

/// Particles sorted by cell of a cubic grid (a copy of the positions in that order, for the
/// neighbour searches below). Cell coordinates are kept modulo 2^21 per axis, so far-apart
/// cells may share a key: that only adds distance checks, which are exact.
struct CellIndex {
  static constexpr uint64_t kMask = (uint64_t(1) << 21) - 1;
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return (uint64_t(z) & kMask) << 42 | (uint64_t(y) & kMask) << 21 | (uint64_t(x) & kMask);
  }
  std::vector<uint32_t> order;           // particle index of each sorted entry
  std::vector<openvdb::Vec3d> sorted;    // their positions
  std::vector<uint64_t> keys;            // each cell's key, ascending
  std::vector<std::array<int64_t, 3>> coords;  // a cell's coordinates (its first entry's)
  std::vector<uint32_t> start;           // each cell's first entry; one more at the end

  CellIndex(const std::vector<openvdb::Vec3d>& p, double size) {
    auto cellOf = [&](const openvdb::Vec3d& q) {
      return std::array<int64_t, 3>{int64_t(std::floor(q.x() / size)), int64_t(std::floor(q.y() / size)),
                                    int64_t(std::floor(q.z() / size))};
    };
    std::vector<std::pair<uint64_t, uint32_t>> keyed(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
      const auto c = cellOf(p[i]);
      keyed[i] = {key(c[0], c[1], c[2]), uint32_t(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    order.resize(p.size());
    sorted.resize(p.size());
    for (size_t i = 0; i < keyed.size(); ++i) {
      order[i] = keyed[i].second;
      sorted[i] = p[keyed[i].second];
      if (i == 0 || keyed[i].first != keyed[i - 1].first) {
        keys.push_back(keyed[i].first);
        coords.push_back(cellOf(sorted[i]));
        start.push_back(uint32_t(i));
      }
    }
    start.push_back(uint32_t(p.size()));
  }
  /// Index of the cell at offset d from cell c, or -1 if empty.
  long neighbour(size_t c, int dx, int dy, int dz) const {
    const uint64_t k = key(coords[c][0] + dx, coords[c][1] + dy, coords[c][2] + dz);
    const auto it = std::lower_bound(keys.begin(), keys.end(), k);
    return it != keys.end() && *it == k ? long(it - keys.begin()) : -1;
  }
  /// Calls f(i, j) (sorted entries) for every pair closer than `range` (the cell size at most),
  /// each pair once.
  template <class F>
  void forEachPairWithin(double range, F&& f) const {
    const double range2 = range * range;
    // The 13 neighbours after a cell in (z, y, x) order: each pair of cells once. Their keys
    // grow with the cell's, so each is found by a cursor that only moves forward (or, where the
    // coordinates wrap, by a search).
    std::array<std::array<int, 3>, 13> offsets;
    std::array<size_t, 13> cursor{};
    for (int dz = 0, o = 0; dz <= 1; ++dz)
      for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
        for (int dx = (dz || dy) ? -1 : 1; dx <= 1; ++dx) offsets[size_t(o++)] = {dx, dy, dz};
    for (size_t c = 0; c + 1 < start.size(); ++c) {
      const uint32_t b0 = start[c], e0 = start[c + 1];
      for (uint32_t i = b0; i < e0; ++i)
        for (uint32_t j = i + 1; j < e0; ++j)
          if ((sorted[i] - sorted[j]).lengthSqr() < range2) f(i, j);
      for (size_t o = 0; o < offsets.size(); ++o) {
        const auto& d = offsets[o];
        const uint64_t k = key(coords[c][0] + d[0], coords[c][1] + d[1], coords[c][2] + d[2]);
        size_t& n = cursor[o];
        if (n > 0 && keys[n - 1] >= k) n = size_t(std::lower_bound(keys.begin(), keys.end(), k) - keys.begin());
        while (n < keys.size() && keys[n] < k) ++n;  // now the first key >= k
        if (n == keys.size() || keys[n] != k || n == c) continue;
        for (uint32_t i = b0; i < e0; ++i)
          for (uint32_t j = start[n]; j < start[n + 1]; ++j)
            if ((sorted[i] - sorted[j]).lengthSqr() < range2) f(i, j);
      }
    }
  }
};

uint32_t bodiesOf(const std::vector<openvdb::Vec3d>& p, double link, std::vector<uint32_t>& body) {
  const CellIndex index(p, link);
  mf::DisjointSets sets(p.size());  // over sorted entries
  index.forEachPairWithin(link, [&](uint32_t a, uint32_t b) { sets.unite(a, b); });
  std::vector<uint32_t> sortedOf(p.size()), label(p.size(), ~0u);
  for (size_t i = 0; i < p.size(); ++i) sortedOf[index.order[i]] = uint32_t(i);
  body.resize(p.size());
  uint32_t count = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    uint32_t& l = label[sets.root(sortedOf[i])];
    if (l == ~0u) l = count++;
    body[i] = l;
  }
  return count;
}

/// Colour of each body: bodies with particles closer than `near` get different colours;
/// greedy, largest body first. Returns the number of colours.
uint32_t colourBodies(const std::vector<openvdb::Vec3d>& p, const std::vector<uint32_t>& body, uint32_t bodies,
                      double near, std::vector<uint32_t>& colour) {
  colour.assign(bodies, 0);
  if (bodies <= 1) return 1;
  const CellIndex index(p, near);
  // Each cell's entries grouped by body: (body, first, end) into `entries`.
  const size_t cells = index.keys.size();
  std::vector<uint32_t> entries(p.size());
  std::vector<std::array<uint32_t, 3>> groups;
  std::vector<uint32_t> cellGroups(cells + 1);
  for (size_t c = 0; c < cells; ++c) {
    const uint32_t b0 = index.start[c], e0 = index.start[c + 1];
    for (uint32_t i = b0; i < e0; ++i) entries[i] = i;
    std::stable_sort(entries.begin() + b0, entries.begin() + e0,
                     [&](uint32_t x, uint32_t y) { return body[index.order[x]] < body[index.order[y]]; });
    cellGroups[c] = uint32_t(groups.size());
    for (uint32_t i = b0; i < e0; ++i)
      if (i == b0 || body[index.order[entries[i]]] != groups.back()[0]) groups.push_back({body[index.order[entries[i]]], i, i + 1});
      else groups.back()[2] = i + 1;
  }
  cellGroups[cells] = uint32_t(groups.size());
  // An edge between two bodies with particles closer than `near`: checked group against group
  // of neighbouring cells, once per pair of bodies.
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  std::unordered_set<uint64_t> known;
  const double near2 = near * near;
  auto check = [&](size_t c, size_t n) {
    for (uint32_t g = cellGroups[c]; g < cellGroups[c + 1]; ++g)
      for (uint32_t h = (c == n ? g + 1 : cellGroups[n]); h < cellGroups[n + 1]; ++h) {
        const uint32_t x = std::min(groups[g][0], groups[h][0]), y = std::max(groups[g][0], groups[h][0]);
        const uint64_t id = uint64_t(x) << 32 | y;
        if (known.count(id)) continue;
        bool close = false;
        for (uint32_t i = groups[g][1]; i < groups[g][2] && !close; ++i)
          for (uint32_t j = groups[h][1]; j < groups[h][2] && !close; ++j)
            close = (index.sorted[entries[i]] - index.sorted[entries[j]]).lengthSqr() < near2;
        if (close) known.insert(id), edges.emplace_back(x, y);
      }
  };
  for (size_t c = 0; c < cells; ++c) {
    check(c, c);
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = dz ? -1 : 0; dy <= 1; ++dy)
        for (int dx = (dz || dy) ? -1 : 1; dx <= 1; ++dx) {
          const long n = index.neighbour(c, dx, dy, dz);
          if (n >= 0 && size_t(n) != c) check(c, size_t(n));
        }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::vector<uint32_t>> adjacent(bodies);
  for (const auto& [a, b] : edges) adjacent[a].push_back(b), adjacent[b].push_back(a);
  std::vector<uint32_t> size(bodies, 0);
  for (uint32_t b : body) ++size[b];
  std::vector<uint32_t> byDecreasingSize(bodies);
  for (uint32_t b = 0; b < bodies; ++b) byDecreasingSize[b] = b;
  std::stable_sort(byDecreasingSize.begin(), byDecreasingSize.end(), [&](uint32_t a, uint32_t b) { return size[a] > size[b]; });
  constexpr uint32_t kNone = ~0u;
  std::fill(colour.begin(), colour.end(), kNone);
  uint32_t colours = 0;
  std::vector<char> taken;
  for (uint32_t b : byDecreasingSize) {
    taken.assign(colours + 1, 0);
    for (uint32_t n : adjacent[b])
      if (colour[n] != kNone) taken[colour[n]] = 1;
    uint32_t c = 0;
    while (taken[c]) ++c;
    colour[b] = c;
    colours = std::max(colours, c + 1);
  }
  return colours;
}

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

uint32_t findBodies(const std::vector<openvdb::Vec3d>& positions, double link, std::vector<uint32_t>& body) {
  return bodiesOf(positions, link, body);
}

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
