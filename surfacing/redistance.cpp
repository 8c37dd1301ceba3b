#include "redistance.h"

#include <openvdb/tree/LeafManager.h>
#include <openvdb/tree/ValueAccessor.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace mf::surfacing {

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

}  // namespace mf::surfacing
