// Damaged and foreign input files: checkpoints, particle frames and surface frames made with the
// library, then cut short, overwritten with random bytes, edited to values no run writes, or taken
// from another scene. Each must give a std::runtime_error naming the file (any other exception, a
// crash or a hang fails the test), a refused checkpoint must leave the simulation as it was, and
// no reader may leave a file in the temporary folder.
#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointDataGrid.h>
#include <xxhash.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <sstream>

#include "render/preview.h"
#include "render/render_frame.h"
#include "sim/particle_io.h"
#include "pipeline/scene_stages.h"
#include "sim/simulation.h"
#include "sim/vdb_file.h"
#include "surfacing/surface_frame.h"

namespace fs = std::filesystem;

namespace {

// A dam break of 275 particles over two frames of 1/30 s: files of a few tens of KB.
mf::SceneStages tinyStages(std::vector<std::string> sets = {}) {
  sets.insert(sets.begin(), {"solver.particle_spacing=0.01", "scene.end_time=0.1", "render.width=8", "render.height=8",
                             "render.samples=1"});
  return mf::loadSceneStages("dam_break", sets);
}
mf::Scene tinyScene(std::vector<std::string> sets = {}) { return tinyStages(std::move(sets)).scene; }

fs::path testDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("mf_inputs_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
void writeBytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(b.data(), std::streamsize(b.size()));
}

// Points TMPDIR and OPENVDB_TEMP_DIR (OpenVDB's TempFile uses the latter, else the former) at an
// empty folder while it lives.
class TempFolderGuard {
 public:
  explicit TempFolderGuard(const fs::path& dir) : dir_(dir) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    for (const char* var : {"TMPDIR", "OPENVDB_TEMP_DIR"}) {
      const char* v = std::getenv(var);
      saved_.emplace_back(var, v ? std::optional<std::string>(v) : std::nullopt);
      ::setenv(var, dir_.c_str(), 1);
    }
  }
  ~TempFolderGuard() {
    for (const auto& [var, v] : saved_) v ? ::setenv(var, v->c_str(), 1) : ::unsetenv(var);
    fs::remove_all(dir_);
  }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }

 private:
  fs::path dir_;
  std::vector<std::pair<const char*, std::optional<std::string>>> saved_;
};

// The text of the std::runtime_error that f throws; a test failure if it throws none. Any other
// exception propagates and fails the test.
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

struct Damage {
  std::string what;
  std::string bytes;
};

// Cut short at several offsets, and 16 or 4096 bytes overwritten with random bytes at several
// places (start, header, metadata, middle, end).
std::vector<Damage> damagedCopies(const std::string& good) {
  std::vector<Damage> out;
  const size_t n = good.size();
  for (size_t at : {size_t(0), size_t(1), size_t(8), size_t(16), size_t(64), size_t(200), n / 4, n / 2, n - 9, n - 1})
    if (at < n) out.push_back({"cut at " + std::to_string(at), good.substr(0, at)});
  std::mt19937_64 rng(12345);
  for (size_t len : {size_t(16), size_t(4096)})
    for (size_t at : {size_t(0), size_t(8), size_t(40), size_t(100), n / 3, n / 2, n > len ? n - len : 0}) {
      std::string b = good;
      for (size_t k = at; k < std::min(n, at + len); ++k) b[k] = char(rng());
      if (b == good) b[at] = char(~b[at]);  // random bytes equal to the old ones would test nothing
      out.push_back({std::to_string(len) + " random bytes at " + std::to_string(at), b});
    }
  return out;
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

mf::FrameInfo infoFor(const mf::Scene& scene, double time, int frame) { return mf::frameInfoFor(scene, frame, time); }

// ---- checkpoints ------------------------------------------------------------------------------

// Field offsets in format 04 (sim/checkpoint.cpp): the tests check the values found there first,
// so a layout change fails them instead of editing some other bytes.
// Tag and version (8), scene hash (8), frame (4), time (8), next id (8), counters' size (4),
// the counters, the phase count (4) and per phase two counts (16), the attribute mask (4), then
// the particle count (8) and the first array's name.
constexpr size_t kFrameAt = 16, kTimeAt = 20, kPhasesAt = 40 + sizeof(mf::SimulationCounters);
size_t countAt(size_t phases) { return kPhasesAt + 4 + 16 * phases + 4; }

template <class T>
T field(const std::string& b, size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}
template <class T>
void setField(std::string& b, size_t at, T v) {
  std::memcpy(&b[at], &v, sizeof v);
}
// What an editor that knows the format does: a valid checksum over the edited bytes.
void reseal(std::string& b) { setField(b, b.size() - 8, uint64_t(XXH3_64bits(b.data(), b.size() - 8))); }

struct CheckpointFixture {
  mf::Scene scene = tinyScene();
  fs::path dir;
  std::string path, good;
  double time = 0;
  size_t particles = 0;
  explicit CheckpointFixture(const std::string& name) : dir(testDir(name)), path((dir / "checkpoint.bin").string()) {
    mf::Simulation sim(scene);
    sim.advanceTo(1 / scene.frameRate);
    sim.saveCheckpoint(path, 1);
    good = readBytes(path);
    time = sim.time();
    particles = sim.particles().size();
  }
  ~CheckpointFixture() { fs::remove_all(dir); }
  // Loads `bytes` into a fresh simulation: the error text; and the state must be the fresh one.
  std::string refusal(const std::string& bytes) {
    writeBytes(path, bytes);
    mf::Simulation sim(scene);
    const std::string before = stateBytes(sim);
    const std::string e = errorOf([&] { sim.loadCheckpoint(path); });
    EXPECT_TRUE(stateBytes(sim) == before) << "a refused checkpoint changed the state";
    EXPECT_EQ(sim.time(), 0.0);
    return e;
  }
};

TEST(Checkpoints, UndamagedResumesBitIdenticallyAndAnotherScenesIsRefused) {
  // The control for the tests below: the same file, undamaged, is accepted and resumes exactly
  // (the loaded bytes are the saved bytes, and the rest of the state is recomputed as it was).
  CheckpointFixture ck("resume");
  mf::Simulation straight(ck.scene);
  straight.advanceTo(1 / ck.scene.frameRate);  // frames end exactly on their time, as in a run
  straight.advanceTo(2 / ck.scene.frameRate);
  mf::Simulation resumed(ck.scene);
  EXPECT_EQ(resumed.loadCheckpoint(ck.path), 1);
  EXPECT_EQ(resumed.time(), ck.time);
  resumed.advanceTo(2 / ck.scene.frameRate);
  EXPECT_TRUE(stateBytes(resumed) == stateBytes(straight));
  EXPECT_EQ(resumed.stepCount(), straight.stepCount());

  // The scene's simulation hash is in the file: another end time is another scene.
  mf::Simulation other(tinyScene({"scene.end_time=0.11"}));
  const std::string e = errorOf([&] { other.loadCheckpoint(ck.path); });
  EXPECT_EQ(e.rfind(ck.path + ": ", 0), 0u) << e;
  EXPECT_NE(e.find("different scene"), std::string::npos) << e;
}

TEST(Checkpoints, DamagedOrCutShortIsRefusedNamingTheFile) {
  // Every damage changes bytes the checksum covers (or the checksum, or the tag before it), so
  // none can pass, and the message starts with the path and says what to do.
  CheckpointFixture ck("damaged");
  TempFolderGuard tmp(ck.dir / "tmp");
  for (const Damage& d : damagedCopies(ck.good)) {
    const std::string e = ck.refusal(d.bytes);
    EXPECT_EQ(e.rfind(ck.path + ": ", 0), 0u) << d.what << ": " << e;
    EXPECT_NE(e.find("delete it to simulate from the start"), std::string::npos) << d.what << ": " << e;
  }
  // 16 bytes changed inside the particle arrays resumed silently before checksums: a mismatch now.
  std::string b = ck.good;
  for (size_t k = 0; k < 16; ++k) b[ck.good.size() / 2 + k] ^= char(0x5a);
  EXPECT_NE(ck.refusal(b).find("checksum mismatch, the file is damaged"), std::string::npos);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(Checkpoints, ValuesNoRunWritesAreRefusedEvenWithAValidChecksum) {
  // A NaN time resumed with 0 steps, a huge count ended in bad_alloc: these edits come with a
  // valid checksum (reseal), so only the checks after it can refuse them.
  CheckpointFixture ck("values");
  TempFolderGuard tmp(ck.dir / "tmp");
  ASSERT_EQ(field<int32_t>(ck.good, kFrameAt), 1);
  ASSERT_EQ(field<double>(ck.good, kTimeAt), ck.time);
  ASSERT_EQ(field<uint32_t>(ck.good, kPhasesAt), ck.scene.phases.size());
  const size_t kCountAt = countAt(ck.scene.phases.size()), kFirstNameAt = kCountAt + 8;
  ASSERT_EQ(field<uint64_t>(ck.good, kCountAt), ck.particles);
  ASSERT_EQ(field<uint32_t>(ck.good, kFirstNameAt), 2u);
  ASSERT_EQ(ck.good.substr(kFirstNameAt + 4, 2), "id");
  const size_t n = ck.particles;
  const size_t phaseAt = kFirstNameAt + 4 + 2 + 4 + 8 * n + 4 + 5 + 4;  // after the ids: "phase", uint16
  const size_t positionAt = phaseAt + 2 * n + 4 + 8 + 4;                // "position", 3 doubles
  ASSERT_EQ(ck.good.substr(phaseAt - 9, 5), "phase");
  ASSERT_EQ(ck.good.substr(positionAt - 12, 8), "position");

  struct Edit {
    std::function<void(std::string&)> apply;
    std::string expected;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Edit> edits = {
      {[&](std::string& b) { setField(b, kTimeAt, nan); }, "time nan s is not in"},
      {[&](std::string& b) { setField(b, kTimeAt, -1.0); }, "time -1 s is not in"},
      {[&](std::string& b) { setField(b, kTimeAt, 1e9); }, "time 1000000000 s is not in"},
      {[&](std::string& b) { setField(b, kFrameAt, int32_t(-1)); }, "frame -1 is outside"},
      {[&](std::string& b) { setField(b, kFrameAt, int32_t(1000000)); }, "frame 1000000 is outside"},
      {[&](std::string& b) { setField(b, kPhasesAt, uint32_t(ck.scene.phases.size() + 1)); }, "checkpoint layout differs (phases)"},
      {[&](std::string& b) { setField(b, kCountAt, uint64_t(1) << 62); }, "particle count 4611686018427387904 is more"},
      {[&](std::string& b) { setField(b, kCountAt, uint64_t(n + 1)); }, "checkpoint layout differs"},
      {[&](std::string& b) { setField(b, kFirstNameAt, uint32_t(0xffffffff)); }, "is 4294967295 bytes long"},
      {[&](std::string& b) { setField(b, phaseAt, uint16_t(7)); }, "particle 0 is invalid (phase 7 of 1"},
      {[&](std::string& b) { setField(b, positionAt, nan); }, "array \"position\" holds a non-finite value"},
      {[&](std::string& b) { b.insert(b.size() - 8, "extra"); }, "bytes after the last effect"},
  };
  for (const Edit& edit : edits) {
    std::string b = ck.good;
    edit.apply(b);
    // Unsealed, the checksum refuses the edit before any value is looked at.
    EXPECT_NE(ck.refusal(b).find("checksum mismatch"), std::string::npos) << edit.expected;
    reseal(b);
    const std::string e = ck.refusal(b);
    EXPECT_EQ(e.rfind(ck.path + ": ", 0), 0u) << e;
    EXPECT_NE(e.find(edit.expected), std::string::npos) << e;
  }
  // An older format is named as such, not as damage.
  std::string old = ck.good;
  old[7] = '2';
  EXPECT_NE(ck.refusal(old).find("checkpoint format \"02\""), std::string::npos);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(Checkpoints, HugeFileIsRefusedBeforeReading) {
  // A sparse file of 1 GiB (no disk used) is far more than 275 particles, or the domain's
  // lattice, need: refused by its size, not read (reading it would find no tag instead).
  CheckpointFixture ck("huge");
  fs::resize_file(ck.path, uint64_t(1) << 30);
  mf::Simulation sim(ck.scene);
  const std::string e = errorOf([&] { sim.loadCheckpoint(ck.path); });
  EXPECT_EQ(e.rfind(ck.path + ": ", 0), 0u) << e;
  EXPECT_NE(e.find("more than a checkpoint of this scene can hold"), std::string::npos) << e;
}

// ---- particle and surface files ---------------------------------------------------------------

struct FrameFixture {
  mf::SceneStages stages = tinyStages();
  const mf::Scene& scene = stages.scene;
  fs::path dir;
  std::string path, good;
  explicit FrameFixture(const std::string& name) : dir(testDir(name)), path((dir / "particles.0001.vdb").string()) {
    mf::Simulation sim(scene);
    sim.advanceTo(1 / scene.frameRate);
    mf::writeParticleFrame(path, sim.particles(), infoFor(scene, sim.time(), 1));
    good = readBytes(path);
  }
  ~FrameFixture() { fs::remove_all(dir); }
};

// Reads a VDB file's grids, lets `edit` change them, and writes them back sealed (a valid
// checksum, as writeParticleFrame and surfaceFrame write): the checks after the checksum are
// then what must find the problem.
void rewriteSealed(const std::string& path, const std::function<void(openvdb::GridPtrVec&)>& edit, bool seal = true) {
  openvdb::GridPtrVec grids;
  {
    std::ifstream in(path, std::ios::binary);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    grids = *stream.getGrids();
  }
  edit(grids);
  openvdb::MetaMap meta;
  if (seal) meta.insertMeta(mf::kVdbChecksumKey, openvdb::StringMetadata(mf::vdbChecksumPlaceholder()));
  std::ostringstream os(std::ios::binary);
  openvdb::io::Stream(os).write(grids, meta);
  std::string bytes = os.str();
  if (seal) mf::sealVdbFile(bytes);
  writeBytes(path, bytes);
}

// An edit of a VDB file's grids, and what the error must then say.
struct VdbEdit {
  std::function<void(openvdb::GridPtrVec&)> apply;
  std::string expected;
  bool seal = true;
};

TEST(ParticleFiles, DamagedOrCutShortGiveAnErrorNamingTheFile) {
  // Before checksums these gave aborts, crashes, 24 GB of memory or library text. Now the size
  // and checksum are checked before OpenVDB parses a byte, through every stage that reads them.
  FrameFixture f("particles");
  const std::string surface = (f.dir / "surface.0001.vdb").string(), png = (f.dir / "preview.png").string();
  TempFolderGuard tmp(f.dir / "tmp");
  ASSERT_EQ(mf::readParticleFrame(f.path).size(), 275u);  // the control: undamaged, it reads
  for (const Damage& d : damagedCopies(f.good)) {
    writeBytes(f.path, d.bytes);
    const std::string e = errorOf([&] { mf::readParticleFrame(f.path); });
    EXPECT_EQ(e.rfind(f.path + ": not a readable particle file (", 0), 0u) << d.what << ": " << e;
    const std::string mesh = (f.dir / "mesh").string();
    EXPECT_EQ(errorOf([&] { mf::surfacing::surfaceFrame(f.path, f.scene, f.stages.surfacing, surface, mesh, 1); }), e) << d.what;
    EXPECT_EQ(errorOf([&] { mf::render::renderPreview(f.path, f.scene, f.stages.render, png); }), e) << d.what;
  }
  EXPECT_FALSE(fs::exists(surface));
  EXPECT_FALSE(fs::exists(png));
  // Random damage anywhere, many times: a checksum mismatch each time (not a lucky offset).
  std::mt19937_64 rng(7);
  for (int k = 0; k < 200; ++k) {
    std::string b = f.good;
    const size_t at = rng() % (b.size() - 16);
    for (size_t j = 0; j < 16; ++j) b[at + j] = char(rng());
    writeBytes(f.path, b);
    if (b != f.good) {
      EXPECT_EQ(errorOf([&] { mf::readParticleFrame(f.path); }).rfind(f.path + ": ", 0), 0u);
    }
  }
  // A missing file and a directory are named too.
  EXPECT_EQ(errorOf([&] { mf::readParticleFrame(f.path + ".missing"); }).rfind(f.path + ".missing: ", 0), 0u);
  EXPECT_EQ(errorOf([&] { mf::readParticleFrame(f.dir.string()); }).rfind(f.dir.string() + ": ", 0), 0u);
  // A file over the size limit (sparse, no disk used) is refused without reading it.
  fs::resize_file(f.path, mf::kMaxVdbFileBytes + 1);
  EXPECT_NE(errorOf([&] { mf::readParticleFrame(f.path); }).find("more than the limit of 16 GiB"), std::string::npos);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(ParticleFiles, MissingAttributesWrongMetadataAndNoChecksumAreNamed) {
  // Files that pass the checksum (rewritten and sealed) but lack what the reader needs.
  FrameFixture f("attributes");
  TempFolderGuard tmp(f.dir / "tmp");
  using PointGrid = openvdb::points::PointDataGrid;
  auto points = [](openvdb::GridPtrVec& g) { return openvdb::gridPtrCast<PointGrid>(g.at(0)); };
  const std::vector<VdbEdit> edits = {
      {[&](openvdb::GridPtrVec&) {}, "no multifluid checksum", false},
      {[&](openvdb::GridPtrVec& g) { openvdb::points::dropAttributes(points(g)->tree(), {"phase"}); }, "no attribute \"phase\""},
      {[&](openvdb::GridPtrVec& g) { openvdb::points::dropAttributes(points(g)->tree(), {"id"}); }, "no attribute \"id\""},
      {[&](openvdb::GridPtrVec& g) { openvdb::points::dropAttributes(points(g)->tree(), {"v"}); }, "no attribute \"v\""},
      {[&](openvdb::GridPtrVec& g) {
         g[0]->removeMeta("time");
         g[0]->insertMeta("time", openvdb::StringMetadata("soon"));
       },
       "metadata \"time\" missing or not a double"},
      {[&](openvdb::GridPtrVec& g) { g[0]->removeMeta("phase_names"); }, "metadata \"phase_names\" missing"},
      {[&](openvdb::GridPtrVec& g) {
         g[0]->removeMeta("particle_spacing");
         g[0]->insertMeta("particle_spacing", openvdb::DoubleMetadata(-1));
       },
       "particle_spacing -1 is not a spacing"},
      {[&](openvdb::GridPtrVec& g) { g[0]->setName("other"); }, "no point grid named \"points\""},
  };
  for (const VdbEdit& edit : edits) {
    writeBytes(f.path, f.good);
    rewriteSealed(f.path, edit.apply, edit.seal);
    const std::string e = errorOf([&] { mf::readParticleFrame(f.path); });
    EXPECT_EQ(e.rfind(f.path + ": not a readable particle file (", 0), 0u) << e;
    EXPECT_NE(e.find(edit.expected), std::string::npos) << e;
  }
  // Sealed, but OpenVDB's own header is broken: OpenVDB's error, named. (Read with delayed
  // loading, this case left an openvdb_temp_* file: the copy is made before the header is read.)
  std::string b = f.good;
  const size_t digits = b.find(mf::kVdbChecksumKey) + std::strlen(mf::kVdbChecksumKey) + 14;
  b.replace(digits, 16, mf::vdbChecksumPlaceholder());
  b[0] = char(~b[0]);
  mf::sealVdbFile(b);
  writeBytes(f.path, b);
  const std::string e = errorOf([&] { mf::readParticleFrame(f.path); });
  EXPECT_EQ(e, f.path + ": not a readable particle file (OpenVDB: IoError: not a VDB file)");
  // The control: rewritten without an edit and sealed, it reads.
  writeBytes(f.path, f.good);
  rewriteSealed(f.path, [](openvdb::GridPtrVec&) {});
  EXPECT_EQ(mf::readParticleFrame(f.path).size(), 275u);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(ParticleFiles, FromAnotherSceneAreRefusedBeforeSurfacingAndPreview) {
  // Phase indices mean the writer's phases, and the spacing sets the kernel and voxels: a frame
  // of other phases or spacing would surface silently wrong. The scene name is not compared.
  FrameFixture f("foreign");
  TempFolderGuard tmp(f.dir / "tmp");
  const std::string surface = (f.dir / "surface.0001.vdb").string(), png = (f.dir / "preview.png").string();
  const auto frame = mf::readParticleFrame(f.path);
  mf::ParticleSet ps;
  for (size_t i = 0; i < frame.size(); ++i) {
    mf::ParticleInit p;
    p.position = frame.position[i];
    p.mass = 1;
    ps.append(uint64_t(frame.id[i]), p);
  }
  ps.density.assign(ps.size(), 1000.0);
  ps.pressure.assign(ps.size(), 0.0);
  auto write = [&](mf::FrameInfo info) { mf::writeParticleFrame(f.path, ps, info); };
  auto both = [&](const std::string& expected) {
    for (const std::string& e :
         {errorOf([&] { mf::surfacing::surfaceFrame(f.path, f.scene, f.stages.surfacing, surface, (f.dir / "mesh").string(), 1); }),
          errorOf([&] { mf::render::renderPreview(f.path, f.scene, f.stages.render, png); })})
      EXPECT_EQ(e, f.path + ": " + expected);
  };
  mf::FrameInfo info = infoFor(f.scene, 0, 1);
  info.phaseNames = {"water", "oil"};
  write(info);
  both("written by a scene with phases water,oil; this scene has water");
  info.phaseNames = {"oil"};
  write(info);
  both("written by a scene with phases oil; this scene has water");
  info = infoFor(f.scene, 0, 1);
  info.particleSpacing = 0.02;
  write(info);
  both("written by a scene with particle spacing 0.02 m; this scene has 0.01 m");
  EXPECT_FALSE(fs::exists(surface));
  EXPECT_FALSE(fs::exists(png));
  // The control: within 1e-9 of the spacing, and under another scene name, it surfaces.
  info.particleSpacing = 0.01 * (1 + 1e-12);
  info.sceneName = "a_copy_of_dam_break";
  write(info);
  EXPECT_FALSE(mf::surfacing::surfaceFrame(f.path, f.scene, f.stages.surfacing, surface, (f.dir / "mesh").string(), 1).skipped);
  EXPECT_TRUE(fs::exists(surface));
  EXPECT_TRUE(tmp.files().empty());
}

TEST(SurfaceFiles, DamagedForeignOrNotLevelSetsGiveAnErrorNamingTheFile) {
  // The render stage reads surface.NNNN.vdb; every failure must name it, before rendering.
  FrameFixture f("surface");
  TempFolderGuard tmp(f.dir / "tmp");
  const std::string surface = (f.dir / "surface.0001.vdb").string(), png = (f.dir / "render.png").string();
  mf::surfacing::surfaceFrame(f.path, f.scene, f.stages.surfacing, surface, (f.dir / "mesh").string(), 1);
  const std::string good = readBytes(surface);
  auto render = [&](const mf::SceneStages& s) { return errorOf([&] { mf::render::renderFrame(surface, s.scene, s.render, "", png, 1); }); };
  for (const Damage& d : damagedCopies(good)) {
    writeBytes(surface, d.bytes);
    const std::string e = render(f.stages);
    EXPECT_EQ(e.rfind(surface + ": not a readable surface file (", 0), 0u) << d.what << ": " << e;
  }
  EXPECT_FALSE(fs::exists(png));
  // Sealed, but not what the scene's render.phases need.
  const std::vector<VdbEdit> edits = {
      {[](openvdb::GridPtrVec&) {}, "no multifluid checksum", false},
      {[](openvdb::GridPtrVec& g) { g[0]->setGridClass(openvdb::GRID_FOG_VOLUME); }, "grid \"water\" is not a level set"},
      {[](openvdb::GridPtrVec& g) {
         auto vec = openvdb::Vec3SGrid::create();
         vec->setName("water");
         g[0] = vec;
       },
       "grid \"water\" is a Tree_vec3s_5_4_3, not a float grid"},
      {[](openvdb::GridPtrVec& g) { g[0]->setName("oil"); }, "no level set \"water\""},
  };
  for (const VdbEdit& edit : edits) {
    writeBytes(surface, good);
    rewriteSealed(surface, edit.apply, edit.seal);
    const std::string e = render(f.stages);
    EXPECT_EQ(e.rfind(surface + ": ", 0), 0u) << e;
    EXPECT_NE(e.find(edit.expected), std::string::npos) << e;
  }
  // Another scene's render.phases: the two-fluid scene draws "light" and "heavy".
  writeBytes(surface, good);
  const mf::SceneStages twoFluids = mf::loadSceneStages("two_fluids_mixed", {"render.width=8", "render.height=8", "render.samples=1"});
  EXPECT_EQ(render(twoFluids), surface + ": no level set \"light\" (is it in surfacing.phases?)");
  // The control: undamaged, it renders.
  EXPECT_FALSE(mf::render::renderFrame(surface, f.scene, f.stages.render, "", png, 1).skipped);
  EXPECT_TRUE(fs::exists(png));
  EXPECT_TRUE(tmp.files().empty());
}

TEST(TempFiles, TheGuardSeesOpenVdbsDelayedLoadingCopies) {
  // Why the empty-folder checks above can fail: OpenVDB's delayed loading (io::Stream's default)
  // copies the file into the folder the guard points TMPDIR at, and removes it only when the
  // grids go away; a crash or exit before that left openvdb_temp_* files behind.
  FrameFixture f("guard");
  TempFolderGuard tmp(f.dir / "tmp");
  {
    std::ifstream in(f.path, std::ios::binary);
    openvdb::io::Stream stream(in);  // delayLoad = true
    ASSERT_EQ(tmp.files().size(), 1u);
    EXPECT_EQ(tmp.files()[0].rfind("openvdb_temp_", 0), 0u);
  }
  EXPECT_TRUE(tmp.files().empty());
  // Our reader makes none, even while reading.
  mf::readParticleFrame(f.path);
  EXPECT_TRUE(tmp.files().empty());
}

}  // namespace
