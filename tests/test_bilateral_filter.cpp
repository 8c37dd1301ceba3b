// surfacing::bilateralFilter against the filter evaluated directly, voxel by voxel through an
// accessor, with std::exp for the range weight: the tool copies each leaf's neighbourhood into a
// padded block and reads the range weight from a table (relative error under 1e-4), so the two
// agree to that, at a stencil inside one neighbour leaf and at one that reaches past it.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>

#include "surfacing/bilateral_filter.h"

namespace {

// One pass of the bilateral mean at every active voxel of `grid`, straight from the definition.
openvdb::FloatGrid::Ptr directPass(const openvdb::FloatGrid& grid, int radius, double spatialSigma, double rangeSigma) {
  auto out = grid.deepCopy();
  const double voxel = grid.voxelSize()[0];
  auto acc = grid.getConstAccessor();
  auto dst = out->getAccessor();
  for (auto v = grid.cbeginValueOn(); v; ++v) {
    if (!v.isVoxelValue()) continue;
    const openvdb::Coord ijk = v.getCoord();
    const double centre = *v;
    double sum = 0, wsum = 0;
    for (int k = -radius; k <= radius; ++k)
      for (int j = -radius; j <= radius; ++j)
        for (int i = -radius; i <= radius; ++i) {
          const int r2 = i * i + j * j + k * k;
          if (r2 > radius * radius) continue;
          const double value = acc.getValue(ijk + openvdb::Coord(i, j, k)), dv = value - centre;
          const double w = std::exp(-0.5 * r2 / (spatialSigma * spatialSigma)) *
                           std::exp(-dv * dv / (2 * rangeSigma * voxel * rangeSigma * voxel));
          sum += w * value;
          wsum += w;
        }
    dst.setValue(ijk, float(sum / wsum));
  }
  return out;
}

void expectMatchesDirect(int radius, double spatialSigma) {
  openvdb::initialize();
  const float voxel = 0.01f;
  // A sphere of 9 voxels with a band wide enough for the stencil to read distances, not background.
  const auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.09f, openvdb::Vec3f(0.003f, -0.002f, 0.001f), voxel,
                                                                               float(radius + 3));
  const auto direct = directPass(*sphere, radius, spatialSigma, 2.0);
  auto filtered = sphere->deepCopy();
  mf::surfacing::bilateralFilter(*filtered, radius, spatialSigma, 2.0, 1);
  auto a = filtered->getConstAccessor(), b = direct->getConstAccessor();
  double worst = 0;
  size_t n = 0;
  for (auto v = sphere->cbeginValueOn(); v; ++v, ++n) worst = std::max(worst, double(std::fabs(a.getValue(v.getCoord()) - b.getValue(v.getCoord()))));
  EXPECT_GT(n, 1000u);
  // Measured 6.7e-8 m (radius 3) and 1.1e-7 m (radius 9): float rounding and the table's error,
  // which is smooth in the difference and largely cancels. Bound 1e-6 m; a block copied only from
  // the adjacent leaves (stale beyond them) gives 2.4e-5 m at radius 9.
  EXPECT_LT(worst, 1e-6) << "radius " << radius;
}

TEST(BilateralFilter, MatchesTheDefinitionWithinOneNeighbourLeaf) { expectMatchesDirect(3, 2.0); }

// A wide spatial weight, so that the taps beyond the neighbour leaves count (at 9 voxels 0.32 of
// the centre's; at sigma 2 they would weigh 4e-5 and a wrong block there would pass).
TEST(BilateralFilter, MatchesTheDefinitionWhenTheStencilReachesPastTheNeighbourLeaf) { expectMatchesDirect(9, 6.0); }

TEST(BilateralFilter, LeavesAPlaneWhereItIs) {
  // phi = z - 0.0437 on a block of voxels: every stencil is symmetric about its centre. Four
  // passes of radius 3 read 12 voxels around the column checked, all inside the block.
  openvdb::initialize();
  const double voxel = 0.01;
  auto grid = openvdb::FloatGrid::create(0.05f);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  auto acc = grid->getAccessor();
  for (int k = -20; k <= 20; ++k)
    for (int j = -12; j <= 12; ++j)
      for (int i = -12; i <= 12; ++i) acc.setValue(openvdb::Coord(i, j, k), float(k * voxel - 0.0437));
  auto filtered = grid->deepCopy();
  mf::surfacing::bilateralFilter(*filtered, 3, 2.0, 2.0, 4);
  auto f = filtered->getConstAccessor();
  for (int k = -8; k <= 8; ++k) EXPECT_NEAR(f.getValue(openvdb::Coord(0, 0, k)), k * voxel - 0.0437, 1e-6) << k;
}

}  // namespace
