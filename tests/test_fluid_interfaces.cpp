// Where two fluids touch, their level sets meet (surfacing/fluid_interfaces.h): no film of
// nothing between them, an overlap no thicker than asked, nothing changed away from the
// interface, and fluids that stand apart stay apart.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <tbb/global_control.h>

#include <cmath>

#include "lattice_util.h"
#include "surfacing/fluid_interfaces.h"
#include "surfacing/particle_surface.h"

using openvdb::Vec3d;

namespace {

constexpr double kSpacing = 0.01;

// A lattice filling [lo, hi), jittered by 0.2 spacings.
std::vector<Vec3d> block(const Vec3d& lo, const Vec3d& hi, uint32_t seed) { return mf::test::lattice(lo, hi, kSpacing, 0.2, seed); }

struct Layers {
  std::vector<openvdb::FloatGrid::Ptr> levelSets;  // lower, upper
  openvdb::FloatGrid::Ptr united;
  double voxel;
};

// A lower fluid in y < 0.3 and an upper one above it, their nearest particles `apart` spacings
// apart across the interface (1: one lattice; density contrast leaves about 1.1-1.4 in a run).
Layers layers(double apart) {
  const mf::SurfacingSettings s;
  const auto lower = block(Vec3d(0.2, 0.2, 0.2), Vec3d(0.4, 0.3, 0.4), 1);
  const auto upper = block(Vec3d(0.2, 0.3 + (apart - 1) * kSpacing, 0.2), Vec3d(0.4, 0.4, 0.4), 2);
  std::vector<Vec3d> all = lower;
  all.insert(all.end(), upper.begin(), upper.end());
  Layers out;
  out.levelSets = {mf::surfacing::particlesToSurface(lower, {}, kSpacing, s).levelSet,
                   mf::surfacing::particlesToSurface(upper, {}, kSpacing, s).levelSet};
  out.united = mf::surfacing::particlesToSurface(all, {}, kSpacing, s).levelSet;
  out.voxel = s.voxelRatio * kSpacing;
  return out;
}

// Along vertical lines through the interface's middle (x, z in [0.25, 0.35]): the longest run
// where neither fluid is inside (the film), and where both are (the overlap), in voxels.
struct Profile {
  double film = 0, overlap = 0;
};
Profile profile(const Layers& l) {
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> a(*l.levelSets[0]), b(*l.levelSets[1]);
  Profile p;
  const double step = 0.02 * l.voxel;
  for (double x = 0.25; x <= 0.35; x += 0.0137)
    for (double z = 0.25; z <= 0.35; z += 0.0113) {
      double film = 0, overlap = 0;
      for (double y = 0.27; y <= 0.34; y += step) {
        const bool inA = a.wsSample(Vec3d(x, y, z)) < 0, inB = b.wsSample(Vec3d(x, y, z)) < 0;
        film = (!inA && !inB) ? film + step : 0;
        overlap = (inA && inB) ? overlap + step : 0;
        p.film = std::max(p.film, film / l.voxel);
        p.overlap = std::max(p.overlap, overlap / l.voxel);
      }
    }
  return p;
}

}  // namespace

TEST(FluidInterfaces, TouchingFluidsMeetWithoutAFilmAndOverlapByAsMuchAsAsked) {
  // Surfaced apart, two layers whose particles stand 1.3 spacings apart leave a film of about
  // 0.4 spacings (0.8 voxels) where neither is inside: the renderer drew it as two interfaces
  // with air between (a grey band between the lamp's wax and its liquid). Closed, no film is
  // left, and the overlap is the asked 2 x 0.5 voxels; the tolerance of 0.25 voxels is the
  // trilinear sampling of two kinked fields on a 0.02-voxel march.
  for (double apart : {1.0, 1.3, 1.6}) {
    Layers l = layers(apart);
    const Profile before = profile(l);
    const size_t flipped = mf::surfacing::closeFluidInterfaces(l.levelSets, *l.united, float(0.5 * l.voxel));
    const Profile after = profile(l);
    std::printf("particles %.1f spacings apart: film %.2f voxels before, %.2f after; overlap %.2f before, %.2f after; "
                "%zu voxels changed sign\n",
                apart, before.film, after.film, before.overlap, after.overlap, flipped);
    EXPECT_EQ(after.film, 0.0) << apart;
    EXPECT_LT(after.overlap, std::max(before.overlap, 1.0) + 0.25) << apart;
    if (apart >= 1.3) {
      EXPECT_GT(before.film, 0.3) << "the case no longer shows a film to close: " << apart;
      EXPECT_GT(flipped, 0u);
      EXPECT_GT(after.overlap, 0.5) << apart;  // measured 0.78 and 1.00: the voxels inside keep their values
    }
  }
}

TEST(FluidInterfaces, NothingChangesAwayFromTheInterfaceOrBetweenFluidsThatStandApart) {
  // Three spacings between the layers' particles: the united level set has the gap too, so
  // nothing is filled: no voxel changes sign, and the voxels that place the zero crossing
  // (within 1.5 voxels of it) move by less than 0.001 voxels. The united set is the same
  // particles surfaced again, renormalised with both layers, and where it is lower by its
  // rounding (measured 0.00015 voxels) it wins; further out, a value may drop more, to the
  // united set's renormalised kink between the layers.
  {
    Layers l = layers(3.0);
    const float near = float(1.5 * l.voxel);
    const auto a0 = l.levelSets[0]->deepCopy(), b0 = l.levelSets[1]->deepCopy();
    EXPECT_EQ(mf::surfacing::closeFluidInterfaces(l.levelSets, *l.united, float(0.5 * l.voxel)), 0u);
    for (auto [now, was] : {std::pair{l.levelSets[0], a0}, std::pair{l.levelSets[1], b0}}) {
      auto acc = now->getConstAccessor();
      size_t checked = 0;
      for (auto it = was->cbeginValueOn(); it; ++it) {
        ASSERT_EQ(acc.getValue(it.getCoord()) < 0, *it < 0) << it.getCoord();
        if (std::fabs(*it) >= near) continue;
        ASSERT_NEAR(acc.getValue(it.getCoord()), *it, 0.001 * l.voxel) << it.getCoord();
        ++checked;
      }
      EXPECT_GT(checked, 1000u);
    }
  }
  Layers l = layers(1.3);
  const auto a0 = l.levelSets[0]->deepCopy();
  const openvdb::FloatGrid::Ptr upper = l.levelSets[1];  // before: the call replaces the grids
  const auto b0 = upper->getConstAccessor();
  mf::surfacing::closeFluidInterfaces(l.levelSets, *l.united, float(0.5 * l.voxel));
  auto was = a0->getConstAccessor();
  size_t far = 0;
  for (auto it = l.levelSets[0]->cbeginValueOn(); it; ++it)
    if (b0.getValue(it.getCoord()) >= upper->background()) {  // beyond the upper fluid's band
      ASSERT_EQ(*it, was.getValue(it.getCoord())) << it.getCoord();
      ++far;
    }
  EXPECT_GT(far, 1000u);
}

TEST(FluidInterfaces, ABubbleInsideWaterKeepsItsSurface) {
  // A bubble of 20 air particles in a cavity of water: the water's field already closes over a
  // cavity this small, so nothing is a gap and the bubble must keep its inside voxels (its
  // priority wins in the renderer), growing by at most the overlap.
  std::vector<Vec3d> water, air;
  const Vec3d c(0.3, 0.3, 0.3);
  for (const Vec3d& p : block(Vec3d(0.2), Vec3d(0.4), 3)) ((p - c).length() < 0.017 ? air : water).push_back(p);
  ASSERT_GE(air.size(), 15u);
  std::vector<Vec3d> all = water;
  all.insert(all.end(), air.begin(), air.end());
  const mf::SurfacingSettings s;
  std::vector<openvdb::FloatGrid::Ptr> ls = {mf::surfacing::particlesToSurface(water, {}, kSpacing, s).levelSet,
                                             mf::surfacing::particlesToSurface(air, {}, kSpacing, s).levelSet};
  const auto united = mf::surfacing::particlesToSurface(all, {}, kSpacing, s).levelSet;
  auto insideCount = [](const openvdb::FloatGrid& g) {
    size_t n = 0;
    for (auto it = g.cbeginValueOn(); it; ++it) n += *it < 0;
    return n;
  };
  const size_t before = insideCount(*ls[1]);
  const double voxel = s.voxelRatio * kSpacing;
  mf::surfacing::closeFluidInterfaces(ls, *united, float(0.5 * voxel));
  const size_t after = insideCount(*ls[1]);
  std::printf("bubble of %zu particles: %zu inside voxels before, %zu after\n", air.size(), before, after);
  EXPECT_GE(after, before);
  EXPECT_LT(double(after), 2.0 * double(before));  // half a voxel more on a radius of about 3.5 voxels
}

TEST(FluidInterfaces, SameBitsOnAnyThreadCount) {
  auto closed = [](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    Layers l = layers(1.3);
    mf::surfacing::closeFluidInterfaces(l.levelSets, *l.united, float(0.5 * l.voxel));
    return l.levelSets;
  };
  const auto one = closed(1), three = closed(3);
  for (size_t f = 0; f < 2; ++f) {
    ASSERT_EQ(one[f]->activeVoxelCount(), three[f]->activeVoxelCount());
    auto acc = three[f]->getConstAccessor();
    for (auto it = one[f]->cbeginValueOn(); it; ++it) ASSERT_EQ(*it, acc.getValue(it.getCoord())) << it.getCoord();
  }
}
