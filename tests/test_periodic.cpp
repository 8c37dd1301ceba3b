// Periodic boundaries (scene.periodic): the neighbour search finds neighbours across the faces
// as brute force over the nearest images does, a lattice that tiles the period has one density
// everywhere (no seam), particles wrap without loss, and a shear wave across the period decays
// at the viscous rate exp(-nu k^2 t) of the Navier-Stokes equations. Surfacing continues the
// surface through a periodic face and cuts it flat there.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "sim/neighbor_search.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "surfacing/particle_surface.h"
#include "surfacing/periodic_images.h"

namespace {

using mf::Real;
using mf::Vec3;

TEST(Periodic, NeighboursMatchBruteForceOverTheNearestImages) {
  // Periodic in x and z, not y; the query grid and the searched grid have different origins
  // (as the fluid and a wider wall grid do).
  const mf::PeriodicDomain pd{0b101, {0, 0, 0}, {0.3, 0.4, 0.25}};
  const Real h = 0.05;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  auto points = [&](size_t n) {
    std::vector<Vec3> p(n);
    for (auto& x : p) x = {u(rng) * 0.3, u(rng) * 0.4, u(rng) * 0.25};
    return p;
  };
  std::vector<Vec3> a = points(2000), b = points(1500);
  a[0] = {0, 0.2, 0};          // on the lower faces
  a[1] = {0.3 - 1e-12, 0.2, 0.25 - 1e-12};  // just inside the upper ones
  b[0] = {0.299, 0.2, 0.249};  // a corner image of a[0] at 1.4e-3 m
  mf::CellGrid ga, gb;
  ga.build(a.data(), a.size(), {-0.1, -0.1, -0.1}, h);
  gb.build(b.data(), b.size(), {-0.17, -0.13, -0.11}, h);
  for (const bool self : {true, false}) {
    const std::vector<Vec3>& other = self ? a : b;
    mf::NeighborLists nl;
    ga.findNeighbors(self ? ga : gb, h, self, nl, pd);
    ASSERT_EQ(nl.rows(), a.size());
    size_t acrossFaces = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      std::vector<uint32_t> expected;
      for (size_t j = 0; j < other.size(); ++j) {
        if (self && i == j) continue;
        if (mf::lengthSquared(pd.separation(a[i], other[j])) < h * h) expected.push_back(uint32_t(j));
        if (mf::lengthSquared(pd.separation(a[i], other[j])) < h * h && mf::lengthSquared(a[i] - other[j]) >= h * h)
          ++acrossFaces;
      }
      std::vector<uint32_t> got(nl.indices.begin() + nl.begin(i), nl.indices.begin() + nl.end(i));
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, expected) << "row " << i << (self ? " (self)" : " (other grid)");
    }
    EXPECT_GT(acrossFaces, 200u);  // the images matter: not vacuous
  }
}

// A box of water, all three axes periodic, no walls, no gravity: `extra` is appended.
std::string periodicBox(const std::string& extra, const std::string& axes = R"(["x", "y", "z"])") {
  return R"([scene]
name = "periodic"
end_time = 0.2
frame_rate = 10
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.1, 0.1, 0.03]
periodic = )" + axes + R"(
[solver]
particle_spacing = 0.005
pressure = "dfsph"
max_dt = 0.005
[[phase]]
name = "water"
rest_density = 1000.0
viscosity = 1.0
)" + extra;
}

Real densitySpread(const mf::ParticleSet& ps) {
  const auto [lo, hi] = std::minmax_element(ps.density.begin(), ps.density.end());
  return (*hi - *lo) / *lo;
}

TEST(Periodic, ALatticeThatTilesThePeriodHasOneDensityAndWrapsWithoutLoss) {
  // The whole box filled, moving along the diagonal at 0.4 m/s: it crosses the x face 0.8
  // times in 0.2 s. A missed image would read ~half the density at a face.
  mf::Simulation sim(mf::parseScene(periodicBox(R"([[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.1, 0.03]
velocity = [0.4, 0.1, 0.05]
[effects.viscosity]
)"),
                                    "periodic.toml"));
  const size_t n = sim.particles().size();
  ASSERT_EQ(n, 20u * 20u * 6u);
  // Equal to rounding (every particle sees the same lattice around it).
  EXPECT_LT(densitySpread(sim.particles()), 1e-12);
  EXPECT_NEAR(sim.particles().density[0], 1000.0, 1e-9);
  sim.advanceTo(0.2);
  const mf::ParticleSet& ps = sim.particles();
  EXPECT_EQ(ps.size(), n);
  EXPECT_EQ(sim.counters().removedOutOfDomain, 0u);
  EXPECT_EQ(sim.counters().wallClamps, 0u);
  for (size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.position[i];
    ASSERT_TRUE(x.x >= 0 && x.x < 0.1 && x.y >= 0 && x.y < 0.1 && x.z >= 0 && x.z < 0.03) << i;
    // Rigid translation: nothing decelerates it (no walls), so the velocity stays.
    ASSERT_NEAR(ps.velocity[i].x, 0.4, 1e-9) << i;
  }
  // Positions move by one shared rounding per step; the density stays uniform to 1e-9.
  EXPECT_LT(densitySpread(ps), 1e-9);
}

TEST(Periodic, AChannelBetweenPlatesTilesItsWallsAcrossTheFaces) {
  // Periodic in x and z, plates at y = 0 and 0.05 (a closed box reaching the periodic faces):
  // every particle of one layer has the density of that layer, seam or not.
  mf::Simulation sim(mf::parseScene(periodicBox(R"([[solid]]
name = "plates"
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.05, 0.03]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.05, 0.03]
)",
                                                R"(["x", "z"])"),
                                    "channel.toml"));
  const mf::ParticleSet& ps = sim.particles();
  ASSERT_EQ(ps.size(), 20u * 10u * 6u);
  for (int layer = 0; layer < 10; ++layer) {
    Real lo = 1e30, hi = 0;
    for (size_t i = 0; i < ps.size(); ++i)
      if (std::lround(ps.position[i].y / 0.005 - 0.5) == layer) lo = std::min(lo, ps.density[i]), hi = std::max(hi, ps.density[i]);
    EXPECT_LT((hi - lo) / lo, 1e-9) << "layer " << layer;
  }
}

// u_x(y, 0) = U sin(k y), k = 2 pi / L, seeded as 20 one-particle slabs across the period.
Real shearWaveAmplitudeRatio(Real t, Real& crossComponent) {
  std::string blocks;
  const Real s = 0.005, U = 0.01, k = 2 * M_PI / 0.1;
  for (int j = 0; j < 20; ++j) {
    const Real y = (j + 0.5) * s;
    blocks += "[[fluid]]\nphase = \"water\"\nmin = [0.0, " + std::to_string(j * s) + ", 0.0]\nmax = [0.1, " +
              std::to_string((j + 1) * s) + ", 0.03]\nvelocity = [" + std::to_string(U * std::sin(k * y)) + ", 0.0, 0.0]\n";
  }
  mf::Simulation sim(mf::parseScene(periodicBox(blocks + "[effects.viscosity]\n"), "wave.toml"));
  EXPECT_EQ(sim.particles().size(), 2400u);
  sim.advanceTo(t);
  const mf::ParticleSet& ps = sim.particles();
  // Least-squares amplitudes of sin(k y) and cos(k y) in u_x.
  Real ss = 0, sc = 0, cc = 0, us = 0, uc = 0;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Real sn = std::sin(k * ps.position[i].y), cs = std::cos(k * ps.position[i].y);
    ss += sn * sn, sc += sn * cs, cc += cs * cs, us += ps.velocity[i].x * sn, uc += ps.velocity[i].x * cs;
  }
  const Real det = ss * cc - sc * sc;
  crossComponent = (ss * uc - sc * us) / det / U;
  return (cc * us - sc * uc) / det / U;
}

TEST(Periodic, AShearWaveAcrossThePeriodDecaysAtTheViscousRate) {
  // nu = 1e-3 m^2/s, k = 2 pi / 0.1 m: exp(-nu k^2 t) = 0.454 at t = 0.2 s. Half or twice the
  // viscosity would give 0.674 or 0.206, so 3 % separates a right viscosity from a wrong one
  // by far; the SPH Laplacian at 20 particles per wavelength and backward Euler at 40 steps
  // are each expected at about 1 %.
  Real cross = 0;
  const Real ratio = shearWaveAmplitudeRatio(0.2, cross);
  const Real expected = std::exp(-1e-3 * std::pow(2 * M_PI / 0.1, 2) * 0.2);
  std::printf("  amplitude ratio %.4f, analytic %.4f (%.2f %%); cos component %.2g\n", ratio, expected,
              100 * (ratio / expected - 1), cross);
  EXPECT_NEAR(ratio / expected, 1.0, 0.03);
  EXPECT_LT(std::fabs(cross), 1e-3);  // the wave does not drift in phase
}

TEST(Periodic, ScenesThatCannotWrapAreRefusedWithTheKey) {
  auto message = [](const std::string& text) {
    try {
      mf::parseScene(text, "p.toml");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string fluid = "[[fluid]]\nphase = \"water\"\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.03]\n";
  EXPECT_NE(message(periodicBox(fluid, R"(["x", "w"])")).find("\"w\" is not one of \"x\", \"y\", \"z\""), std::string::npos);
  EXPECT_NE(message(periodicBox(fluid, R"(["x", "x"])")).find("listed twice"), std::string::npos);
  // 0.03 m along z with h = 0.01 m is allowed; 0.015 m is not.
  std::string thin = periodicBox(fluid);
  thin.replace(thin.find("domain_max = [0.1, 0.1, 0.03]"), 29, "domain_max = [0.1, 0.1, 0.015]");
  const std::string t = message(thin);
  EXPECT_NE(t.find("scene.periodic"), std::string::npos) << t;
  EXPECT_NE(t.find("two support radii (0.02 m)"), std::string::npos) << t;
  const std::string narrow = message(periodicBox(
      "[[solid]]\nname = \"tank\"\nshape = \"box\"\nmin = [0.01, 0.0, 0.0]\nmax = [0.1, 0.05, 0.03]\n" + fluid, R"(["x"])"));
  EXPECT_NE(narrow.find("solid[0].min"), std::string::npos) << narrow;
  EXPECT_NE(narrow.find("must reach the domain's faces"), std::string::npos) << narrow;
}

// The level set of a slab of lattice particles filling the period along x, 5 layers deep.
openvdb::FloatGrid::Ptr slabLevelSet(bool withImages, const mf::PeriodicDomain& pd) {
  const Real s = 0.01;
  std::vector<openvdb::Vec3d> p;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 20; ++i) p.emplace_back((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s);
  const mf::SurfacingSettings settings;
  if (withImages) {
    std::vector<openvdb::Vec3d> images;
    mf::surfacing::periodicImages(p, pd, 0.1, images);
    p.insert(p.end(), images.begin(), images.end());
  }
  auto surface = mf::surfacing::particlesToSurface(p, {}, s, settings);
  if (withImages) mf::surfacing::cutAtPeriodicFaces(*surface.levelSet, pd);
  return surface.levelSet;
}

TEST(Periodic, TheSurfaceContinuesThroughAPeriodicFaceAndIsCutFlatThere) {
  openvdb::initialize();
  const mf::PeriodicDomain pd{0b001, {0, 0, 0}, {0.2, 1, 1}};
  const auto phiAt = [](const openvdb::FloatGrid& g, double x, double y) {
    return openvdb::tools::BoxSampler::sample(g.tree(), g.transform().worldToIndex(openvdb::Vec3d(x, y, 0.05)));
  };
  const auto wrapped = slabLevelSet(true, pd), plain = slabLevelSet(false, pd);
  const double voxel = wrapped->transform().voxelSize()[0];
  // Height of the top surface (phi = 0, by bisection between y = 0.03 and 0.08 m).
  const auto surfaceAt = [&](const openvdb::FloatGrid& g, double x) {
    double lo = 0.03, hi = 0.08;
    for (int k = 0; k < 40; ++k) (phiAt(g, x, 0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  };
  // The largest difference, in voxels, between the surface 1.5 voxels inside a face (clear of
  // the cut, which bounds phi by the distance to the face) and at mid-period.
  const auto seamError = [&](const openvdb::FloatGrid& g) {
    const double mid = surfaceAt(g, 0.1);
    return std::max(std::fabs(surfaceAt(g, 1.5 * voxel) - mid), std::fabs(surfaceAt(g, 0.2 - 1.5 * voxel) - mid)) / voxel;
  };
  const double withImages = seamError(*wrapped), without = seamError(*plain);
  std::printf("  surface height at the face against mid-period: %.3f voxels with images, %.3f without\n", withImages, without);
  // The lattice tiles the period and the voxels tile it too, so with images x = 1.5 voxels sees
  // what x = 0.1 m sees (measured 0.000 voxels; 0.02 allows the filter's rounding).
  EXPECT_LT(withImages, 0.02);
  EXPECT_GT(without, 0.5);  // what the images fix: the slab rounds off at its ends
  // Beyond the faces the fluid is cut: outside, one voxel out, on both sides; inside just within.
  EXPECT_GT(phiAt(*wrapped, -voxel, 0.02), 0);
  EXPECT_GT(phiAt(*wrapped, 0.2 + voxel, 0.02), 0);
  EXPECT_LT(phiAt(*wrapped, 0.5 * voxel, 0.02), 0);
}

}  // namespace
