// Every shipped scene's frame 0, through the real stages (seeded particles -> surfacing -> the
// renderer's camera): the fluid is in the picture. Coverage is the share of pixels whose centre
// ray, straight through the glass, meets a fluid surface (PathTracer::coverage).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "render/render_frame.h"
#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;

namespace {

double frameZeroCoverage(const std::string& name) {
  // Small and fast: coverage needs no samples, only the camera and the surfaces.
  const mf::Scene scene = mf::loadScene(name, {"render.width=96", "render.height=54"});
  const fs::path dir = fs::temp_directory_path() / ("mf_framing_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(dir);
  mf::Simulation sim(scene);
  const mf::FrameInfo info = mf::frameInfoFor(scene);
  const std::string particles = (dir / "particles.vdb").string(), surface = (dir / "surface.vdb").string();
  mf::writeParticleFrame(particles, sim.particles(), info);
  mf::surfacing::surfaceFrame(particles, scene, surface, "", 0);
  const auto r = mf::render::renderFrame(surface, scene, "", "", 0);
  fs::remove_all(dir);
  return r.fluidCoverage;
}

}  // namespace

TEST(Framing, EveryShippedSceneShowsItsFluidAtFrameZero) {
  for (const std::string& name : mf::embeddedSceneNames()) {
    const double c = frameZeroCoverage(name);
    RecordProperty(name, std::to_string(c));
    std::printf("  %-18s fluid covers %.1f %% of frame 0\n", name.c_str(), 100 * c);
    // The bar: at least 5 % of the pixels. Before the scenes had framing, five of the
    // seven showed their container as a speck from the default camera at (0.5, 0.5, 2).
    EXPECT_GE(c, 0.05) << name;
  }
}

TEST(Framing, WithoutCameraKeysTheSolidsAreFramedAndTheTableIsUnderThem) {
  // boiling's domain reaches 8 cm below its glass: the table belongs under the glass.
  const mf::Scene scene = mf::loadScene("boiling");
  EXPECT_FALSE(scene.render.cameraFraming.empty());
  EXPECT_NEAR(scene.render.floorHeight, scene.solids[0].base.y - scene.render.solidMaterials[0].thickness, 1e-12);
  EXPECT_GT(scene.render.floorHeight, scene.domainMin.y + 0.05);
  // A scene's own camera is kept as given.
  const mf::Scene dam = mf::loadScene("dam_break");
  EXPECT_TRUE(dam.render.cameraFraming.empty());
  EXPECT_DOUBLE_EQ(dam.render.cameraPosition.z, 0.42);
}
