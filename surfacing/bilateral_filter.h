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

#include <cmath>
#include <vector>

namespace mf::surfacing {

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
  auto rangeWeight = [&](double q) {
    const double x = q * kPerUnit;
    if (x >= kPerUnit * kMaxQ) return kExpTable[kPerUnit * kMaxQ];
    const int i = int(x);
    const double f = x - i;
    return kExpTable[i] + f * (kExpTable[i + 1] - kExpTable[i]);
  };

  using LeafT = typename TreeT::LeafNodeType;
  constexpr int kLeafDim = int(LeafT::DIM);
  const int pad = kLeafDim + 2 * radius;  // each leaf and the stencil's reach around it
  // Stencil offsets as strides into a leaf's padded copy.
  std::vector<std::pair<int, double>> strided;
  for (const Tap& t : taps) strided.emplace_back(t.offset.x() + pad * (t.offset.y() + pad * t.offset.z()), t.weight);

  for (int it = 0; it < iterations; ++it) {
    const TreeT source(grid.tree());  // read the previous pass, write this one
    openvdb::tree::LeafManager<TreeT> leaves(grid.tree());
    leaves.foreach([&](LeafT& leaf, size_t) {
      openvdb::tree::ValueAccessor<const TreeT> acc(source);
      // One accessor lookup per voxel of the padded block instead of one per stencil tap.
      std::vector<double> block(size_t(pad) * pad * pad);
      const openvdb::Coord origin = leaf.origin() - openvdb::Coord(radius);
      for (int z = 0; z < pad; ++z)
        for (int y = 0; y < pad; ++y)
          for (int x = 0; x < pad; ++x)
            block[size_t(x + pad * (y + pad * z))] = double(acc.getValue(origin + openvdb::Coord(x, y, z)));
      for (auto v = leaf.beginValueOn(); v; ++v) {
        const openvdb::Coord local = v.getCoord() - leaf.origin();
        const int c = (local.x() + radius) + pad * ((local.y() + radius) + pad * (local.z() + radius));
        const double centre = block[size_t(c)];
        double sum = 0, wsum = 0;
        for (const auto& [offset, spatial] : strided) {
          const double value = block[size_t(c + offset)];
          const double dv = value - centre;
          const double w = spatial * rangeWeight(rangeFactor * dv * dv);
          sum += w * value;
          wsum += w;
        }
        v.setValue(ValueT(sum / wsum));
      }
    });
  }
}

}  // namespace mf::surfacing
