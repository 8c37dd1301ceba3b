// Every shipped scene's frame 0, through the real stages (seeded particles -> surfacing -> the
// renderer's camera): the fluid is in the picture. Coverage is the share of pixels whose centre
// ray, straight through the glass, meets a fluid surface (PathTracer::coverage).
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "render/camera.h"
#include "render/path_tracer.h"
#include "pipeline/scene_stages.h"
#include "render/render_frame.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;

namespace {

double frameZeroCoverage(const std::string& name) {
  // Small and fast: coverage needs no samples, only the camera and the surfaces. The scene's own
  // aspect (the lamp's frame is portrait), 96 pixels on its longer side.
  const mf::SceneStages shipped = mf::loadSceneStages(name);
  const int w = shipped.render.width, h = shipped.render.height, longer = std::max(w, h);
  const mf::SceneStages stages = mf::loadSceneStages(name, {fmt::format("render.width={}", std::max(8, 96 * w / longer)),
                                               fmt::format("render.height={}", std::max(8, 96 * h / longer))});
  const fs::path dir = fs::temp_directory_path() / ("mf_framing_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(dir);
  mf::Simulation sim(stages.scene);
  const mf::FrameInfo info = mf::frameInfoFor(stages.scene);
  const std::string particles = (dir / "particles.vdb").string(), surface = (dir / "surface.vdb").string();
  mf::writeParticleFrame(particles, sim.particles(), info);
  mf::surfacing::surfaceFrame(particles, stages.scene, stages.surfacing, surface, "", 0);
  const auto r = mf::render::renderFrame(surface, stages.scene, stages.render, "", "", 0);
  fs::remove_all(dir);
  return r.fluidCoverage;
}

}  // namespace

TEST(Framing, EveryShippedSceneShowsItsFluidAtFrameZero) {
  for (const std::string& name : mf::embeddedSceneNames()) {
    const double c = frameZeroCoverage(name);
    RecordProperty(name, std::to_string(c));
    std::printf("  %-18s fluid covers %.1f %% of frame 0\n", name.c_str(), 100 * c);
    // The issue's bar: at least 5 % of the pixels. Before the scenes had framing, five of the
    // seven showed their container as a speck from the default camera at (0.5, 0.5, 2).
    EXPECT_GE(c, 0.05) << name;
  }
}

TEST(Framing, WithoutCameraKeysTheSolidsAreFramedAndTheTableIsUnderThem) {
  // water_oil's domain reaches 1 cm below its tank: the table belongs under the tank's wall.
  const mf::SceneStages stages = mf::loadSceneStages("water_oil");
  EXPECT_FALSE(stages.render.cameraFraming.empty());
  EXPECT_NEAR(stages.render.floorHeight, stages.scene.solids[0].min.y - stages.render.solidMaterials[0].thickness, 1e-12);
  EXPECT_GT(stages.render.floorHeight, stages.scene.domainMin.y + 0.005);
  // boiling puts its table under the burner, below the glass, by floor_height.
  const mf::SceneStages boiling = mf::loadSceneStages("boiling");
  EXPECT_TRUE(boiling.render.cameraFraming.empty());
  EXPECT_DOUBLE_EQ(boiling.render.floorHeight, -0.065);
  // A scene's own camera is kept as given.
  const mf::SceneStages dam = mf::loadSceneStages("dam_break");
  EXPECT_TRUE(dam.render.cameraFraming.empty());
  EXPECT_DOUBLE_EQ(dam.render.cameraPosition.z, 0.42);
}

// [[render.prop]]: the lamp's base and cap, and any object only the render stage draws. It is
// a surface of the frame (opaque and diffuse by default), counts for the table and the framing,
// and takes no part in the simulation: the same boundary samples and the same simulation hash.
TEST(Props, APropIsDrawnButNotSimulated) {
  const std::string prop =
      "render.prop=[{name=\"stand\", shape=\"cylinder\", base=[0.1, -0.2, 0.1], radius=0.08, height=0.19, "
      "thickness=0.004, colour=[0.3, 0.3, 0.3]}]";
  const mf::SceneStages plain = mf::loadSceneStages("water_oil"), withProp = mf::loadSceneStages("water_oil", {prop});
  ASSERT_EQ(withProp.render.props.size(), 1u);
  const mf::PropSpec& p = withProp.render.props[0];
  EXPECT_EQ(p.shape.name, "stand");
  EXPECT_TRUE(p.material.kind == mf::MaterialSpec::Kind::Diffuse);
  EXPECT_EQ(withProp.scene.simulationHash, plain.scene.simulationHash);
  EXPECT_EQ(mf::Simulation(withProp.scene).boundary().size(), mf::Simulation(plain.scene).boundary().size());
  const auto surfaces = mf::render::solidSurfaces(withProp.scene, withProp.render);
  ASSERT_EQ(surfaces.size(), mf::render::solidSurfaces(plain.scene, plain.render).size() + 1);
  EXPECT_EQ(surfaces.back().name, "stand");
  EXPECT_GT(surfaces.back().mesh.size(), 100u);
  // The table goes under the stand's outer wall, now the lowest thing in the scene.
  EXPECT_NEAR(withProp.render.floorHeight, -0.2 - 0.004, 1e-12);
  // Its keys are checked like a solid's: a named key, a range.
  try {
    mf::loadSceneStages("water_oil", {"render.prop=[{shape=\"cylinder\", base=[0.0, 0.0, 0.0], radius=-1.0, height=0.1}]"});
    FAIL() << "a negative radius must be refused";
  } catch (const mf::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("render.prop[0].radius"), std::string::npos) << e.what();
  }
}

// [[render.camera_key]]: a cubic Hermite spline per coordinate with Catmull-Rom tangents on the
// keys' times, zero at the ends. What must hold whatever the keys: the keys are met exactly, the
// pose is held outside them, the midpoint of two keys is their mean (zero tangents), and the
// velocity is continuous at an inner key (Catmull-Rom's tangent from both sides).
TEST(CameraKeys, TheSplineMeetsTheKeysHoldsOutsideAndIsSmoothAtInnerKeys) {
  const std::string keys =
      "render.camera_key=[{time=0.5, position=[1,0.2,1], look_at=[0,0,0]},"
      " {time=1.0, position=[0,0.4,1.5], look_at=[0,0.1,0], fov=30},"
      " {time=2.5, position=[-1,0.2,1], look_at=[0.1,0,0], fov=50}]";
  const mf::SceneStages stages = mf::loadSceneStages("water_oil", {keys});
  const auto& k = stages.render.cameraKeys;
  ASSERT_EQ(k.size(), 3u);
  EXPECT_TRUE(stages.render.cameraFraming.empty()) << "keys are a camera: no automatic framing";
  EXPECT_DOUBLE_EQ(k[0].fov, 40) << "fov defaults to render.fov";
  using mf::render::cameraAt;
  for (const auto& key : k) {
    const mf::CameraKey c = cameraAt(k, key.time);
    EXPECT_EQ(c.position, key.position);
    EXPECT_EQ(c.lookAt, key.lookAt);
    EXPECT_EQ(c.fov, key.fov);
  }
  EXPECT_EQ(cameraAt(k, 0.0).position, k[0].position);
  EXPECT_EQ(cameraAt(k, 9.0).position, k[2].position);
  // Between the first two keys the second has tangent (p2 - p0) / 2 s; the mean holds for the
  // first and the last segment only where both ends' tangents are zero: check with two keys.
  const std::vector<mf::CameraKey> two(k.begin(), k.begin() + 2);
  const mf::CameraKey mid = cameraAt(two, 0.75);
  EXPECT_NEAR(mid.position.y, 0.3, 1e-12);
  EXPECT_NEAR(mid.fov, 35, 1e-12);
  // Velocity at the inner key from both sides against Catmull-Rom's (p2 - p0) / (t2 - t0).
  const double e = 1e-6;
  const mf::Vec3 left = (cameraAt(k, 1.0).position - cameraAt(k, 1.0 - e).position) / e;
  const mf::Vec3 right = (cameraAt(k, 1.0 + e).position - cameraAt(k, 1.0).position) / e;
  const mf::Vec3 want = (k[2].position - k[0].position) / (k[2].time - k[0].time);
  for (int a = 0; a < 3; ++a) {
    // One-sided differences are off by the curvature times e: 1e-5 is far above that (|p''| < 10
    // m/s^2 here) and far below the tangent's 0.5 m/s.
    EXPECT_NEAR(left[a], want[a], 1e-5) << a;
    EXPECT_NEAR(right[a], want[a], 1e-5) << a;
  }
  // At the end keys the camera comes to rest.
  EXPECT_NEAR(mf::length(cameraAt(k, 2.5 - e).position - k[2].position) / e, 0, 1e-5);
}

TEST(CameraKeys, ARenderedFrameUsesThePoseAtItsTime) {
  // water_oil at 25 frames/s: a camera on the tank at frame 0 that turns away from it by frame 5
  // (0.2 s). Frame 0 shows the fluid, frame 5 sees none of it.
  const mf::SceneStages framed = mf::loadSceneStages("water_oil");
  const mf::Vec3 eye = framed.render.cameraPosition, at = framed.render.lookAt;
  const mf::Vec3 away = eye + (eye - at);  // looking straight away from the tank
  const std::string keys = fmt::format(
      "render.camera_key=[{{time=0, position=[{},{},{}], look_at=[{},{},{}]}}, {{time=0.2, position=[{},{},{}], look_at=[{},{},{}]}}]",
      eye.x, eye.y, eye.z, at.x, at.y, at.z, eye.x, eye.y, eye.z, away.x, away.y, away.z);
  const mf::SceneStages stages = mf::loadSceneStages("water_oil", {"render.width=96", "render.height=54", keys});
  const fs::path dir = fs::temp_directory_path() / ("mf_camera_keys_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  mf::Simulation sim(stages.scene);
  const std::string particles = (dir / "particles.vdb").string(), surface = (dir / "surface.vdb").string();
  mf::writeParticleFrame(particles, sim.particles(), mf::frameInfoFor(stages.scene));
  mf::surfacing::surfaceFrame(particles, stages.scene, stages.surfacing, surface, "", 0);
  const double at0 = mf::render::renderFrame(surface, stages.scene, stages.render, "", "", 0).fluidCoverage;
  const double at5 = mf::render::renderFrame(surface, stages.scene, stages.render, "", "", 5).fluidCoverage;
  fs::remove_all(dir);
  EXPECT_GE(at0, 0.05);
  EXPECT_EQ(at5, 0.0);
}

TEST(CameraKeys, BadKeysAreNamedWithTheirKey) {
  auto problems = [](const std::string& keys, const std::vector<std::string>& more = {}) {
    std::vector<std::string> o = more;
    o.push_back(keys);
    try {
      mf::loadSceneStages("water_oil", o);
    } catch (const mf::SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string backwards = problems(
      "render.camera_key=[{time=1, position=[1,0,1], look_at=[0,0,0]}, {time=0.5, position=[1,0,1], look_at=[0,0,0]}]");
  EXPECT_NE(backwards.find("render.camera_key[1].time"), std::string::npos) << backwards;
  const std::string missing = problems("render.camera_key=[{time=1, look_at=[0,0,0]}]");
  EXPECT_NE(missing.find("render.camera_key[0].position"), std::string::npos) << missing;
  const std::string both = problems("render.camera_key=[{time=1, position=[1,0,1], look_at=[0,0,0]}]",
                                    {"render.camera_position=[1,1,1]"});
  EXPECT_NE(both.find("not both"), std::string::npos) << both;
}

TEST(DefaultMaterials, FollowWhatTheEffectsMakeOfAPhaseNotItsName) {
  // A gas named "foo" that buoyancy lifts is a bubble; a liquid named "oil" without a material
  // is the second liquid, dyed red (names carry no look); the first liquid is water.
  const char* text = R"(
[scene]
name = "roles"
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.1, 0.1, 0.1]
[solver]
particle_spacing = 0.01
[[phase]]
name = "water"
rest_density = 1000.0
[[phase]]
name = "foo"
rest_density = 100.0
[[phase]]
name = "oil"
rest_density = 800.0
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.05, 0.05, 0.05]
[effects.gravity]
[effects.buoyancy]
[[effects.buoyancy.gas]]
phase = "foo"
coefficient = 1.0
)";
  const mf::SceneStages sc = mf::parseSceneStages(text, "roles.toml", {"solver.pressure=\"dfsph\""});
  const auto& m = sc.render.phaseMaterials;
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].ior, 1.33);
  EXPECT_EQ(m[0].absorption.y, 1.2);  // water's faint blue-green
  EXPECT_EQ(m[1].ior, 1.0);
  EXPECT_EQ(m[1].priority, 20);  // the bubble wins where it overlaps the water
  EXPECT_EQ(m[2].ior, 1.33);
  EXPECT_EQ(m[2].absorption.y, 18.0);  // red: told apart from the water
  // The shipped scenes: pour_glass's trapped air and boiling's vapour are bubbles, boiling's
  // flame glows behind an invisible boundary.
  const mf::SceneStages pour = mf::loadSceneStages("pour_glass"), boil = mf::loadSceneStages("boiling");
  EXPECT_EQ(pour.render.phaseMaterials.at(size_t(pour.scene.phaseIndex("air"))).priority, 20);
  EXPECT_EQ(boil.render.phaseMaterials.at(size_t(boil.scene.phaseIndex("vapour"))).priority, 20);
  EXPECT_EQ(boil.render.phaseMaterials.at(size_t(boil.scene.phaseIndex("flame"))).ior, 1.0);
  EXPECT_EQ(boil.render.phaseMaterials.at(size_t(boil.scene.phaseIndex("flame"))).priority, 5);
}
