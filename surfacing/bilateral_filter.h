// Bilateral filter for narrow-band level sets, in the manner of openvdb/tools: one templated
// entry function, grid passed in and filtered in place.
//
// Each active voxel's value becomes a weighted mean of the values in a spherical stencil, with
// weights that fall with the spatial offset (Gaussian, sigma in voxels) and with the difference
// in distance value (Gaussian, sigma in voxels of distance). Across a smooth surface the values
// of tangential neighbours are close, so the bumps that single particles leave are averaged out;
// across an edge or a thin sheet the values differ by several voxels and those neighbours weigh
// less, so the feature is rounded less than by a Gaussian. A narrow ridge of positive distance,
// the gap between two droplets a voxel or two apart, is still averaged away (a difference of one
// voxel keeps 88 % of the weight at sigma 2): particle_surface.cpp filters each connected body
// of fluid on its own for that reason. For a linear distance
// field the stencil is symmetric (|phi(x+d) - phi(x)| = |phi(x-d) - phi(x)|), so a plane is
// reproduced exactly: the filter does not move flat surfaces.
//
// The result is no longer an exact distance; renormalise afterwards (LevelSetTracker).
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace mf::surfacing {

namespace detail {

/// One voxel's bilateral mean over the taps at `at + offsets[t]` with spatial weights
/// `spatials[t]`, the range weight exp(-rangeFactor dv^2) read from `expTable` (perUnit entries per
/// unit, linear in between, clamped at its end). A function of its own so that the two sums stay
/// in registers: inlined into the leaf loop, GCC kept them in memory and every tap waited on a
/// store (the same arithmetic, in the same order).
[[gnu::noinline]] inline double bilateralMean(const double* at, const int* offsets, const double* spatials, size_t taps,
                                              double rangeFactor, const double* expTable, int perUnit, int maxQ) {
  const double centre = *at, last = double(perUnit * maxQ);
  double sum = 0, wsum = 0;
  for (size_t t = 0; t < taps; ++t) {
    const double value = at[offsets[t]];
    const double dv = value - centre;
    const double x = std::min(rangeFactor * dv * dv * perUnit, last);
    const int i = int(x);
    const double f = x - i;
    const double w = spatials[t] * (expTable[i] + f * (expTable[i + 1] - expTable[i]));
    sum += w * value;
    wsum += w;
  }
  return sum / wsum;
}

}  // namespace detail

/// @brief Filters the active voxels of a level set in place.
/// @param grid          a narrow-band level set (FloatGrid or DoubleGrid)
/// @param radius        stencil radius in voxels (offsets with |d| <= radius)
/// @param spatialSigma  Gaussian width of the spatial weight, voxels
/// @param rangeSigma    Gaussian width of the value weight, voxels of distance (0: plain Gaussian)
/// @param iterations    passes of the filter
template <typename GridT>
void bilateralFilter(GridT& grid, int radius, double spatialSigma, double rangeSigma, int iterations = 1) {
  using ValueT = typename GridT::ValueType;
  using TreeT = typename GridT::TreeType;
  if (radius <= 0 || iterations <= 0) return;
  const double voxel = grid.voxelSize()[0];
  struct Tap {
    openvdb::Coord offset;
    double weight;
  };
  std::vector<Tap> taps;
  for (int k = -radius; k <= radius; ++k)
    for (int j = -radius; j <= radius; ++j)
      for (int i = -radius; i <= radius; ++i) {
        const int r2 = i * i + j * j + k * k;
        if (r2 > radius * radius) continue;
        taps.push_back({openvdb::Coord(i, j, k), std::exp(-0.5 * r2 / (spatialSigma * spatialSigma))});
      }
  // Range weight exp(-q), q = dv^2 / (2 (rangeSigma voxel)^2), from a table (exp was a third of
  // the run time): 64 entries per unit of q up to q = 16, linear in between (relative error
  // below 1e-4), exp(-16) beyond. rangeSigma 0 turns the range weight off.
  const double rangeFactor = rangeSigma > 0 ? 0.5 / (rangeSigma * voxel * rangeSigma * voxel) : 0.0;
  constexpr int kPerUnit = 64, kMaxQ = 16;
  static const std::vector<double> kExpTable = [] {
    std::vector<double> t(kPerUnit * kMaxQ + 2);
    for (size_t i = 0; i < t.size(); ++i) t[i] = std::exp(-double(i) / kPerUnit);
    return t;
  }();
  const double* const expTable = kExpTable.data();

  using LeafT = typename TreeT::LeafNodeType;
  constexpr int kLeafDim = int(LeafT::DIM);
  const int pad = kLeafDim + 2 * radius;  // each leaf and the stencil's reach around it
  const int reach = (radius + kLeafDim - 1) / kLeafDim;  // neighbour leaves either side that the block meets
  // Stencil offsets as strides into a leaf's padded copy.
  std::vector<int> tapOffset;
  std::vector<double> tapWeight;
  for (const Tap& t : taps) {
    tapOffset.push_back(t.offset.x() + pad * (t.offset.y() + pad * t.offset.z()));
    tapWeight.push_back(t.weight);
  }

  for (int it = 0; it < iterations; ++it) {
    const TreeT source(grid.tree());  // read the previous pass, write this one
    openvdb::tree::LeafManager<TreeT> leaves(grid.tree());
    leaves.foreach([&](LeafT& leaf, size_t) {
      openvdb::tree::ValueAccessor<const TreeT> acc(source);
      thread_local std::vector<double> block;
      // The padded block: the leaf and its neighbours' voxels within the stencil's reach, copied
      // a neighbour leaf at a time (a tile or the background fills its part with one value), so
      // that the taps below read an array instead of the tree.
      block.resize(size_t(pad) * pad * pad);
      const openvdb::Coord origin = leaf.origin() - openvdb::Coord(radius);
      for (int nz = -reach; nz <= reach; ++nz)
        for (int ny = -reach; ny <= reach; ++ny)
          for (int nx = -reach; nx <= reach; ++nx) {
            const openvdb::Coord other = leaf.origin() + openvdb::Coord(nx * kLeafDim, ny * kLeafDim, nz * kLeafDim);
            // The part of that leaf inside the padded block, in block coordinates.
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
              lo[a] = std::max(0, other[a] - origin[a]);
              hi[a] = std::min(pad, other[a] + kLeafDim - origin[a]);
            }
            if (lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]) continue;
            const LeafT* src = acc.probeConstLeaf(other);
            const double fill = src ? 0.0 : double(acc.getValue(other));
            for (int z = lo[2]; z < hi[2]; ++z)
              for (int y = lo[1]; y < hi[1]; ++y)
                for (int x = lo[0]; x < hi[0]; ++x)
                  block[size_t(x + pad * (y + pad * z))] =
                      src ? double(src->getValue(origin + openvdb::Coord(x, y, z) - other)) : fill;
          }
      const double* const values = block.data();
      const int* const offsets = tapOffset.data();
      const double* const spatials = tapWeight.data();
      const size_t tapCount = tapOffset.size();
      for (auto v = leaf.beginValueOn(); v; ++v) {
        const openvdb::Coord local = v.getCoord() - leaf.origin();
        const double* const at = values + ((local.x() + radius) + pad * ((local.y() + radius) + pad * (local.z() + radius)));
        v.setValue(ValueT(detail::bilateralMean(at, offsets, spatials, tapCount, rangeFactor, expTable, kPerUnit, kMaxQ)));
      }
    });
  }
}

}  // namespace mf::surfacing
