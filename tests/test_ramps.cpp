// Colour ramps over particle attributes: surfacing's attribute grid (the Shepard kernel average
// of the particles' values) and the path tracer's heterogeneous absorption and emission from it,
// against what they must give analytically, and the scene keys' errors; and the AOVs' motion
// vectors and the motion blur against the projected shift.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "render/path_tracer.h"
#include "render/volume_field.h"
#include "render/blackbody.h"
#include "pipeline/scene_stages.h"
#include "surfacing/attribute_grid.h"

using namespace mf;
using render::PathTracer;
using render::Surface;

namespace {

/// Particles on a cubic lattice of spacing h filling [0, L]^3, their value f(position).
void lattice(double h, double L, const std::function<float(const openvdb::Vec3d&)>& f, std::vector<openvdb::Vec3d>& x,
             std::vector<float>& v) {
  const int n = int(std::lround(L / h));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        x.emplace_back(i * h, j * h, k * h);
        v.push_back(f(x.back()));
      }
}

/// A box as a closed outward mesh (12 triangles).
render::RenderMesh box(const Vec3& lo, const Vec3& hi) {
  SolidSpec s;
  s.shape = SolidSpec::Shape::Box;
  s.min = lo, s.max = hi;
  render::RenderMesh walls = render::solidMesh(s, 0), out;
  out.positions = walls.positions, out.normals = walls.normals;
  out.triangles.assign(walls.triangles.begin(), walls.triangles.begin() + 12);
  return out;
}

/// A field over [lo, hi] on voxels of `voxel`: value f(world position of the voxel centre).
std::shared_ptr<render::VolumeField> field(const Vec3& lo, const Vec3& hi, double voxel, const std::function<float(const Vec3&)>& f) {
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  auto a = g->getAccessor();
  const openvdb::Coord c0 = g->transform().worldToIndexCellCentered(openvdb::Vec3d(lo.x, lo.y, lo.z));
  const openvdb::Coord c1 = g->transform().worldToIndexCellCentered(openvdb::Vec3d(hi.x, hi.y, hi.z));
  for (int i = c0.x(); i <= c1.x(); ++i)
    for (int j = c0.y(); j <= c1.y(); ++j)
      for (int k = c0.z(); k <= c1.z(); ++k) {
        const openvdb::Vec3d w = g->transform().indexToWorld(openvdb::Coord(i, j, k));
        a.setValue(openvdb::Coord(i, j, k), f({w.x(), w.y(), w.z()}));
      }
  return std::make_shared<render::VolumeField>(*g);
}

/// A slab z in [-d, 0] of a clear medium (n = 1) in front of a white emitter, or (black) of
/// nothing, seen straight on: what the centre pixel receives.
Vec3 throughSlab(double d, MaterialSpec slab, std::shared_ptr<render::VolumeField> absorption,
                 std::shared_ptr<render::VolumeField> emission, bool white) {
  std::vector<Surface> surfaces;
  Surface s{"slab", box({-0.1, -0.1, -d}, {0.1, 0.1, 0}), slab};
  s.absorptionField = absorption, s.emissionField = emission;
  surfaces.push_back(std::move(s));
  if (white) {
    MaterialSpec e;
    e.kind = MaterialSpec::Kind::Emitter;
    e.emission = {1, 1, 1};
    surfaces.push_back({"white", box({-1, -1, -0.51}, {1, 1, -0.5}), e});
  }
  RenderSettings rs;
  rs.width = rs.height = 9, rs.samples = 2;
  rs.skyZenith = rs.skyHorizon = rs.skyGround = {0, 0, 0};
  rs.floor = false, rs.lightRadius = 0;
  rs.cameraPosition = {0, 0, 0.5}, rs.lookAt = {0, 0, 0}, rs.fov = 1;
  return PathTracer(std::move(surfaces), rs).render(0).at(4, 4);
}

}  // namespace

TEST(AttributeGrid, ReproducesAConstantAndALinearFieldInsideALattice) {
  const double h = 0.01, L = 0.1;
  const auto xf = openvdb::math::Transform::createLinearTransform(0.5 * h);
  for (const bool linear : {false, true}) {
    std::vector<openvdb::Vec3d> x;
    std::vector<float> v;
    auto f = [&](const openvdb::Vec3d& p) { return linear ? float(20 + 600 * p.x() - 100 * p.y()) : 42.0f; };
    lattice(h, L, f, x, v);
    const auto g = surfacing::attributeGrid(x, v, 2 * h, *xf);
    auto a = g->getConstAccessor();
    size_t inside = 0;
    double worst = 0;
    for (auto it = g->cbeginValueOn(); it; ++it) {
      const openvdb::Vec3d w = xf->indexToWorld(it.getCoord());
      // Inside: the kernel's whole support (2 h) within the lattice, where its symmetry makes
      // the Shepard average of a linear field exact.
      if (w.x() < 2 * h || w.y() < 2 * h || w.z() < 2 * h || w.x() > L - 2 * h || w.y() > L - 2 * h || w.z() > L - 2 * h) continue;
      ++inside;
      worst = std::max(worst, std::fabs(double(*it) - double(f(w))));
    }
    EXPECT_GT(inside, 2000u);
    // Float storage of values up to 80: 1e-4 is a few ulps of the sums' rounding.
    EXPECT_LT(worst, 1e-4) << (linear ? "linear" : "constant");
    // Nothing beyond the support: a voxel 2 h outside the lattice is inactive.
    EXPECT_FALSE(a.isValueOn(xf->worldToIndexCellCentered(openvdb::Vec3d(-2.5 * h, 0.05, 0.05))));
  }
}

TEST(ColourRamps, AbsorptionAndEmissionFromTheFieldMatchBeerLambertAndTheLineIntegral) {
  const double d = 0.05, voxel = 0.002;
  MaterialSpec m;
  m.ior = 1.0;
  m.absorption = {100, 100, 100};  // replaced by the ramp: must not show
  m.absorptionRamp.attribute = "temperature";
  m.absorptionRamp.lo = 20, m.absorptionRamp.hi = 80;
  m.absorptionRamp.colours = {{0, 10, 20}, {30, 40, 60}};  // 1/m at 20 and 80 degrees
  // A constant 50 degrees: sigma = the ramp's middle, (15, 25, 40).
  const Vec3 c = throughSlab(d, m, field({-0.1, -0.1, -0.06}, {0.1, 0.1, 0.01}, voxel, [](const Vec3&) { return 50.f; }), nullptr, true);
  const Vec3 sigma{15, 25, 40};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], std::exp(-sigma[k] * d), 1e-4 * std::exp(-sigma[k] * d)) << k;
  // Linear along the ray, 20 at the back to 80 at the front: sigma is linear too, and the optical
  // depth is its mean times d (the midpoint rule and trilinear interpolation are exact there).
  auto ramp = [&](const Vec3& p) { return float(20 + 60 * std::clamp((p.z + d) / d, 0.0, 1.0)); };
  const Vec3 c2 = throughSlab(d, m, field({-0.1, -0.1, -0.06}, {0.1, 0.1, 0.01}, voxel, ramp), nullptr, true);
  const Vec3 mean{15, 25, 40};
  // The field is clamped outside the slab, so it is linear only inside it: 1e-3 relative allows
  // for the half voxel at each face where the interpolation meets the clamp.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c2[k], std::exp(-mean[k] * d), 1e-3 * std::exp(-mean[k] * d) + 2e-4) << k;
  // Emission without absorption, against black: radiance = the integral of the emission.
  MaterialSpec e;
  e.ior = 1.0;
  e.emissionRamp = m.absorptionRamp;
  e.emissionRamp.colours = {{0, 0, 0}, {12, 6, 3}};
  const Vec3 glow = throughSlab(d, e, nullptr, field({-0.1, -0.1, -0.06}, {0.1, 0.1, 0.01}, voxel, ramp), false);
  const Vec3 want = Vec3{6, 3, 1.5} * d;  // the mean of a linear ramp from 0 to (12, 6, 3)

  for (int k = 0; k < 3; ++k) EXPECT_NEAR(glow[k], want[k], 2e-3 * want[k] + 1e-5) << k;
}

TEST(ColourRamps, SceneKeysAreCheckedWithTheirKey) {
  auto problems = [](const std::vector<std::string>& o) {
    try {
      loadSceneStages("diffusion", o);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(problems({}), "") << "the shipped scene's ramp";
  const std::string notWritten = problems({"surfacing.attributes=[]"});
  EXPECT_NE(notWritten.find("render.material.liquid.absorption_ramp"), std::string::npos) << notWritten;
  EXPECT_NE(notWritten.find("surfacing.attributes"), std::string::npos) << notWritten;
  const std::string badColour = problems({"render.material.liquid.absorption_ramp.colours=[[1, 2, 3]]"});
  EXPECT_NE(badColour.find("absorption_ramp.colours"), std::string::npos) << badColour;
  const std::string badRange = problems({"render.material.liquid.absorption_ramp.range=[80, 20]"});
  EXPECT_NE(badRange.find("absorption_ramp.range"), std::string::npos) << badRange;
  const std::string badAttr = problems({"surfacing.attributes=[\"pressure\"]"});
  EXPECT_NE(badAttr.find("surfacing.attributes"), std::string::npos) << badAttr;
}

// Blackbody colours (sim/blackbody.h) against the Planckian locus's CIE 1931 chromaticities
// (Wyszecki & Stiles, table 1(3.3.4)). The multi-lobe fit of the matching functions is weak
// beyond 650 nm (x-bar / y-bar at 700 nm: 1.3 against the table's 2.8), which pulls cool
// blackbodies towards yellow: measured 0.011 at 1 000 K, 0.004 at 1 500 K, 0.0025 at 2 000 K,
// at most 0.0012 from 2 856 K up. The tolerances are those, rounded up; a wrong Planck law or
// colour matrix moves these points by 0.05 or more.
TEST(Blackbody, ChromaticitiesLieOnThePlanckianLocus) {
  const struct {
    double kelvin, x, y, tolerance;
  } locus[] = {{1000, 0.6528, 0.3444, 0.012}, {1500, 0.5857, 0.3931, 0.005}, {2000, 0.5267, 0.4133, 0.003},
               {2856, 0.4476, 0.4074, 0.002}, {4000, 0.3805, 0.3768, 0.002}, {6500, 0.3135, 0.3236, 0.002}};
  for (const auto& p : locus) {
    const Vec3 c = blackbodyXyz(p.kelvin);
    const double sum = c.x + c.y + c.z;
    EXPECT_NEAR(c.x / sum, p.x, p.tolerance) << p.kelvin << " K";
    EXPECT_NEAR(c.y / sum, p.y, p.tolerance) << p.kelvin << " K";
  }
  // Wien: at 560 nm the luminance rises as exp(-hc / (lambda k T)): from 1 000 to 1 100 K by
  // about exp(25 700 (1/1000 - 1/1100)) = 10.3 (the whole spectrum's weight shifts it a little).
  const double ratio = blackbodyXyz(1100).y / blackbodyXyz(1000).y;
  EXPECT_GT(ratio, 8.0);
  EXPECT_LT(ratio, 12.0);
}

TEST(Blackbody, AnEmissionRampOverTemperatureGlowsLikeABlackbody) {
  const SceneStages sc = loadSceneStages("boiling", {"render.material.flame.emission_ramp={ attribute = \"temperature\", range = [700.0, 1600.0], blackbody = 20.0 }",
                                         "surfacing.attributes=[\"temperature\"]"});
  const ColourRamp& ramp = sc.render.phaseMaterials.at(size_t(sc.scene.phaseIndex("flame"))).emissionRamp;
  ASSERT_FALSE(ramp.empty());
  const auto luminance = [](const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
  EXPECT_NEAR(luminance(ramp.at(1600)), 20.0, 0.05);  // the stated luminance at the top
  // Hotter is brighter and bluer: red dominates at 700 deg C, less so at 1600.
  EXPECT_LT(luminance(ramp.at(1000)), 0.1 * luminance(ramp.at(1600)));
  EXPECT_GT(ramp.at(1600).y / ramp.at(1600).x, ramp.at(900).y / ramp.at(900).x);
  EXPECT_GT(ramp.at(1600).x, ramp.at(1600).z);  // still orange, not white
  auto problem = [](const std::vector<std::string>& sets) {
    try {
      loadSceneStages("boiling", sets);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string dye = problem({"render.material.flame.emission_ramp={ attribute = \"dye\", range = [0.0, 1.0], blackbody = 1.0 }",
                                   "surfacing.attributes=[\"dye\"]"});
  EXPECT_NE(dye.find("emission_ramp.blackbody"), std::string::npos) << dye;
  const std::string both = problem({"render.material.flame.emission_ramp={ attribute = \"temperature\", range = [0.0, 1.0], blackbody = 1.0, colours = [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]] }",
                                    "surfacing.attributes=[\"temperature\"]"});
  EXPECT_NE(both.find("colours or blackbody"), std::string::npos) << both;
}

// Motion vectors (render/aov.h): a plane facing the camera at distance D. Every point of it is
// at depth D, so a sideways move dx of the surface, or -dx of the camera, shifts its image by
// dx / D / (tan(fov/2) aspect) * width/2 pixels, everywhere on it.
TEST(MotionVectors, SurfaceVelocityAndCameraMoveGiveTheProjectedShift) {
  const double D = 0.5, dt = 0.04;
  auto render = [&](const Vec3& velocity, const Vec3& cameraMove, render::Aovs& aovs) {
    std::vector<Surface> surfaces;
    MaterialSpec diffuse;
    diffuse.kind = MaterialSpec::Kind::Diffuse;
    Surface s{"plane", box({-1, -1, -0.01}, {1, 1, 0}), diffuse};
    s.mesh.velocities.assign(s.mesh.positions.size(), {float(velocity.x), float(velocity.y), float(velocity.z)});
    surfaces.push_back(std::move(s));
    RenderSettings rs;
    rs.width = 32, rs.height = 18, rs.samples = 4, rs.floor = false;
    rs.cameraPosition = {0, 0, D}, rs.lookAt = {0, 0, 0}, rs.fov = 30;
    RenderSettings next = rs;
    next.cameraPosition += cameraMove, next.lookAt += cameraMove;
    PathTracer tracer(std::move(surfaces), rs);
    tracer.setNextFrame(next, dt);
    tracer.render(0, nullptr, {}, nullptr, &aovs);
  };
  const double perMetre = 1 / D / (std::tan(15 * M_PI / 180) * 32.0 / 18.0) * 32 / 2;  // pixels per m of sideways move
  render::Aovs surface, camera;
  render({0.5, -0.25, 0}, {}, surface);                 // the plane moves right and down
  render({}, {-0.02, 0.01, 0}, camera);                // the camera moves left and up: the same image shift
  for (int p : {0, 17 * 32 / 2 + 5, 18 * 32 - 1}) {
    EXPECT_NEAR(surface.motion[2 * p], 0.5 * dt * perMetre, 1e-4) << p;
    EXPECT_NEAR(surface.motion[2 * p + 1], 0.25 * dt * perMetre, 1e-4) << p;  // image y points down
    EXPECT_NEAR(camera.motion[2 * p], 0.02 * perMetre, 1e-4) << p;
    EXPECT_NEAR(camera.motion[2 * p + 1], 0.01 * perMetre, 1e-4) << p;
  }
}

// Motion blur (render.shutter): a square facing the camera at distance D moves sideways at v.
// Over the shutter its image sweeps w = v shutter dt perMetre pixels, so each row of its
// coverage is the still row convolved with a box of width w: the same total, the same centroid
// (the shutter is centred on the frame) and a variance larger by w^2 / 12.
TEST(MotionBlur, AMovingSquareSmearsOverItsProjectedPathCentredOnTheFrame) {
  const double D = 0.5, dt = 0.04, v = 1.5;
  const int W = 64, H = 36;
  auto row = [&](double shutter) {
    MaterialSpec diffuse;
    diffuse.kind = MaterialSpec::Kind::Diffuse;
    Surface s{"square", box({-0.05, -0.05, -0.01}, {0.05, 0.05, 0}), diffuse};
    s.mesh.velocities.assign(s.mesh.positions.size(), {float(v), 0.0f, 0.0f});
    std::vector<Surface> surfaces;
    surfaces.push_back(std::move(s));
    RenderSettings rs;
    rs.width = W, rs.height = H, rs.samples = 256, rs.floor = false, rs.maxDepth = 1;
    rs.cameraPosition = {0, 0, D}, rs.lookAt = {0, 0, 0}, rs.fov = 30;
    rs.shutter = shutter;
    PathTracer tracer(std::move(surfaces), rs, dt);
    render::Aovs aovs;
    tracer.render(0, nullptr, {}, nullptr, &aovs);
    // The rows the square covers whole (it spans 13.4 of the 36 around the middle), summed.
    std::vector<double> m(W);
    for (int y = H / 2 - 5; y < H / 2 + 5; ++y)
      for (int x = 0; x < W; ++x) m[x] += aovs.mask[size_t(y * W + x)] / 10;
    return m;
  };
  struct Moments {
    double total = 0, centroid = 0, variance = 0;
  };
  auto moments = [](const std::vector<double>& m) {
    Moments r;
    for (size_t x = 0; x < m.size(); ++x) r.total += m[x], r.centroid += (x + 0.5) * m[x];
    r.centroid /= r.total;
    for (size_t x = 0; x < m.size(); ++x) r.variance += (x + 0.5 - r.centroid) * (x + 0.5 - r.centroid) * m[x];
    r.variance /= r.total;
    return r;
  };
  const double perMetre = 1 / D / (std::tan(15 * M_PI / 180) * double(W) / H) * W / 2;
  const Moments still = moments(row(0));
  EXPECT_NEAR(still.total, 0.1 * perMetre, 0.5);  // the square's width in pixels
  for (const double shutter : {0.5, 1.0}) {
    const Moments blurred = moments(row(shutter));
    const double expected = v * shutter * dt * perMetre, measured = std::sqrt(12 * (blurred.variance - still.variance));
    std::printf("  shutter %.1f: smear %.3f px (expected %.3f), total %.3f vs %.3f, centroid %+.3f px\n", shutter, measured,
                expected, blurred.total, still.total, blurred.centroid - still.centroid);
    // 256 samples per pixel over 10 rows: the smear to 3 %, the coverage and centre to 0.1 px.
    EXPECT_NEAR(measured / expected, 1.0, 0.03) << shutter;
    EXPECT_NEAR(blurred.total, still.total, 0.1) << shutter;
    EXPECT_NEAR(blurred.centroid, still.centroid, 0.1) << shutter;
  }
}

TEST(MotionBlur, TheShutterNeedsTheVelocityGrids) {
  try {
    loadSceneStages("dam_break", {"render.shutter=0.5"});
    FAIL() << "accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("render.shutter"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("surfacing.velocity = true"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(loadSceneStages("dam_break", {"render.shutter=0.5", "surfacing.velocity=true"}));
}
