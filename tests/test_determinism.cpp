// Same scene, same bits: across thread counts, across a checkpoint and resume, and in the
// written OpenVDB files (which Houdini and OpenVDB's own reader must read).
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointCount.h>
#include <openvdb/points/PointDataGrid.h>
#include <tbb/global_control.h>

#include <cstring>
#include <limits>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/particle_io.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace fs = std::filesystem;

namespace {

// The dam break at a quarter of its resolution, run over the impact on the far wall.
mf::Scene smallDamBreak() {
  return mf::loadScene("dam_break", {"solver.particle_spacing=0.00714", "scene.end_time=0.3"});
}

std::string stateBytes(mf::Simulation& sim) {
  std::string bytes;
  sim.mutableParticles().forEachArray([&](const char*, const auto& v) {
    bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  });
  const double t = sim.time();
  bytes.append(reinterpret_cast<const char*>(&t), sizeof t);
  return bytes;
}

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("mf_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

mf::FrameInfo infoFor(const mf::Simulation& sim, int frame) { return mf::frameInfoFor(sim.scene(), frame, sim.time()); }

TEST(Determinism, BitIdenticalAcrossThreadCounts) {
  const mf::Scene scene = smallDamBreak();
  const fs::path dir = tempDir("threads");
  std::string reference, referenceFile;
  for (int threads : {1, 2, 3, 8}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    mf::Simulation sim(scene);
    sim.advanceTo(0.15);
    const std::string bytes = stateBytes(sim);
    const fs::path file = dir / ("frame_" + std::to_string(threads) + ".vdb");
    mf::writeParticleFrame(file.string(), sim.particles(), infoFor(sim, 1));
    if (reference.empty()) {
      reference = bytes;
      referenceFile = fileBytes(file);
      EXPECT_GT(sim.stepCount(), 50u);  // DFSPH: 78 steps to 0.15 s, the front at the far wall
    } else {
      EXPECT_TRUE(bytes == reference) << threads << " threads: state differs from 1 thread";
      EXPECT_TRUE(fileBytes(file) == referenceFile) << threads << " threads: file bytes differ";
    }
  }
  fs::remove_all(dir);
}

TEST(Determinism, ResumeFromCheckpointIsBitIdentical) {
  const mf::Scene scene = smallDamBreak();
  const fs::path dir = tempDir("resume");
  mf::Simulation straight(scene);
  straight.advanceTo(0.1);
  straight.advanceTo(0.2);

  mf::Simulation first(scene);
  first.advanceTo(0.1);
  first.saveCheckpoint((dir / "ck.bin").string(), 3);
  mf::Simulation resumed(scene);  // a fresh process would start here
  EXPECT_EQ(resumed.loadCheckpoint((dir / "ck.bin").string()), 3);
  EXPECT_EQ(resumed.time(), first.time());
  resumed.advanceTo(0.2);
  EXPECT_TRUE(stateBytes(resumed) == stateBytes(straight));
  EXPECT_EQ(resumed.stepCount(), straight.stepCount());

  // A checkpoint of another scene is refused.
  mf::Simulation other(mf::loadScene("dam_break", {"solver.particle_spacing=0.00714", "scene.end_time=0.31"}));
  EXPECT_THROW(other.loadCheckpoint((dir / "ck.bin").string()), std::runtime_error);
  fs::remove_all(dir);
}

TEST(ParticleFiles, ReadBackWithOpenVdbsOwnFileReader) {
  const mf::Scene scene = smallDamBreak();
  mf::Simulation sim(scene);
  sim.advanceTo(0.05);
  const fs::path dir = tempDir("io");
  const fs::path file = dir / "particles.0001.vdb";
  mf::writeParticleFrame(file.string(), sim.particles(), infoFor(sim, 1));
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));

  // As a DCC tool opens it: io::File, a grid named "points" with the expected attributes.
  openvdb::initialize();
  openvdb::io::File f(file.string());
  f.open(false);  // delayed loading would copy the file to TMPDIR
  auto grid = openvdb::gridPtrCast<openvdb::points::PointDataGrid>(f.readGrid("points"));
  f.close();
  ASSERT_TRUE(grid);
  const auto leaf = grid->tree().cbeginLeaf();
  ASSERT_TRUE(leaf);
  const auto& d = leaf->attributeSet().descriptor();
  for (const char* name : {"P", "v", "id", "pscale", "phase", "density", "pressure"})
    EXPECT_NE(d.find(name), openvdb::points::AttributeSet::INVALID_POS) << name;
  EXPECT_EQ(d.find("temperature"), openvdb::points::AttributeSet::INVALID_POS);  // not in this scene
  EXPECT_EQ(openvdb::points::pointCount(grid->tree()), sim.particles().size());

  // A non-finite value never reaches a file, whoever produced it.
  mf::ParticleSet broken = sim.particles();
  broken.velocity[3].x = std::numeric_limits<double>::infinity();
  const fs::path bad = dir / "particles.0002.vdb";
  EXPECT_THROW(mf::writeParticleFrame(bad.string(), broken, infoFor(sim, 2)), std::runtime_error);
  EXPECT_FALSE(fs::exists(bad));
  EXPECT_FALSE(fs::exists(bad.string() + ".tmp"));

  // And through our reader: every particle, matched by id, at its position (float precision).
  const mf::ParticleFrame frame = mf::readParticleFrame(file.string());
  ASSERT_EQ(frame.size(), sim.particles().size());
  EXPECT_EQ(frame.info.sceneName, "dam_break");
  EXPECT_EQ(frame.info.phaseNames, std::vector<std::string>{"water"});
  std::vector<size_t> byId(sim.particles().size());
  for (size_t i = 0; i < sim.particles().size(); ++i) byId[sim.particles().id[i]] = i;
  for (size_t k = 0; k < frame.size(); ++k) {
    const size_t i = byId[size_t(frame.id[k])];
    EXPECT_LT(mf::length(frame.position[k] - sim.particles().position[i]), 1e-6);
    EXPECT_NEAR(frame.scalars.at("density")[k], sim.particles().density[i], 1e-3);
  }
  fs::remove_all(dir);
}

}  // namespace
