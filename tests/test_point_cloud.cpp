// Particles as PLY point clouds (surfacing.points_ply): the header names every attribute, the
// body holds one record per particle, and the values read back are the particle file's.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/particle_io.h"
#include "pipeline/scene_stages.h"
#include "sim/simulation.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;

TEST(PointCloud, SurfacingWritesEveryParticleWithItsAttributes) {
  const mf::SceneStages stages = mf::loadSceneStages("dam_break", {"surfacing.points_ply=true", "solver.particle_spacing=0.00714"});
  const mf::Scene& scene = stages.scene;
  const fs::path dir = fs::temp_directory_path() / ("mf_points_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  mf::Simulation sim(scene);
  const mf::FrameInfo info = mf::frameInfoFor(scene);
  const std::string particles = (dir / "particles" / "particles.0000.vdb").string();
  fs::create_directories(dir / "particles");
  mf::writeParticleFrame(particles, sim.particles(), info);
  const auto r = mf::surfacing::surfaceFrame(particles, scene, stages.surfacing, (dir / "surface" / "surface.0000.vdb").string(), (dir / "mesh").string(), 0);
  const fs::path ply = dir / "points" / "points.0000.ply";
  ASSERT_TRUE(fs::exists(ply));
  EXPECT_NE(std::find(r.written.begin(), r.written.end(), ply.string()), r.written.end());

  const mf::ParticleFrame frame = mf::readParticleFrame(particles);
  std::ifstream in(ply, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = bytes.substr(0, end);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex " + std::to_string(frame.size()) + "\n"), std::string::npos) << header;
  for (const auto& [name, values] : frame.scalars) EXPECT_NE(header.find("property float " + name + "\n"), std::string::npos) << name;
  // x y z vx vy vz (float), id (double), phase (int), pscale (float), then the scalars (float).
  const size_t record = 6 * 4 + 8 + 4 + 4 + 4 * frame.scalars.size();
  ASSERT_EQ(bytes.size(), end + 11 + record * frame.size());
  for (size_t i : {size_t(0), frame.size() / 2, frame.size() - 1}) {
    const char* p = bytes.data() + end + 11 + i * record;
    float x[3];
    double id;
    std::memcpy(x, p, 12);
    std::memcpy(&id, p + 24, 8);
    EXPECT_EQ(x[0], float(frame.position[i].x));
    EXPECT_EQ(x[2], float(frame.position[i].z));
    EXPECT_EQ(id, double(frame.id[i]));
  }
  fs::remove_all(dir);
}
