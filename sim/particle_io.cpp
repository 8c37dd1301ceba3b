#include "particle_io.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointDataGrid.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "file_util.h"
#include "scene_file.h"
#include "vdb_file.h"

namespace mf {

FrameInfo frameInfoFor(const Scene& scene, int frame, double time) {
  FrameInfo info;
  info.frame = frame;
  info.time = time;
  info.sceneName = scene.name;
  info.particleSpacing = scene.solver.particleSpacing;
  for (const auto& p : scene.phases) info.phaseNames.push_back(p.name);
  return info;
}


namespace {

void initOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

template <class T>
void addAttribute(openvdb::points::PointDataGrid& grid, const openvdb::tools::PointIndexGrid& index,
                  const std::string& name, const std::vector<T>& values) {
  using namespace openvdb::points;
  appendAttribute<T>(grid.tree(), name);
  populateAttribute<PointDataTree, openvdb::tools::PointIndexTree, PointAttributeVector<T>>(
      grid.tree(), index.tree(), name, PointAttributeVector<T>(values));
}

}  // namespace

void writeParticleFrame(const std::string& path, const ParticleSet& ps, const FrameInfo& info) {
  initOpenVdb();
  using namespace openvdb::points;
  const size_t n = ps.size();
  std::vector<openvdb::Vec3d> positions(n);
  std::vector<openvdb::Vec3f> velocities(n);
  std::vector<int64_t> ids(n);
  std::vector<int32_t> phases(n);
  std::vector<float> pscale(n, float(0.5 * info.particleSpacing));
  for (size_t i = 0; i < n; ++i) {
    // The watchdog keeps invalid states out of the solver; this keeps them out of files too.
    if (!isFinite(ps.position[i]) || !isFinite(ps.velocity[i]) || !std::isfinite(ps.density[i]))
      throw std::runtime_error(fmt::format("{}: not written: particle id {} has a non-finite position, velocity or density",
                                           path, ps.id[i]));
    positions[i] = {ps.position[i].x, ps.position[i].y, ps.position[i].z};
    velocities[i] = {float(ps.velocity[i].x), float(ps.velocity[i].y), float(ps.velocity[i].z)};
    ids[i] = int64_t(ps.id[i]);
    phases[i] = ps.phase[i];
  }
  // Voxels of twice the particle spacing hold about 8 points each: small trees, quick reads.
  const double voxelSize = info.particleSpacing > 0 ? 2 * info.particleSpacing : 0.1;
  auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  PointAttributeVector<openvdb::Vec3d> positionWrapper(positions);
  auto index = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(positionWrapper, *transform);
  auto grid = createPointDataGrid<NullCodec, PointDataGrid>(*index, positionWrapper, *transform);
  grid->setName("points");
  addAttribute(*grid, *index, "v", velocities);
  addAttribute(*grid, *index, "id", ids);
  addAttribute(*grid, *index, "pscale", pscale);
  addAttribute(*grid, *index, "phase", phases);
  auto addScalar = [&](const char* name, const std::vector<Real>& v) {
    std::vector<float> f(v.begin(), v.end());
    addAttribute(*grid, *index, name, f);
  };
  addScalar("density", ps.density);
  std::vector<Real> pressure(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) pressure[i] = ps.mechanicalPressure(i);
  addScalar("pressure", pressure);
  if (ps.has(Attribute::Temperature)) addScalar("temperature", ps.temperature);
  if (ps.has(Attribute::InterfaceColour)) addScalar("interfaceColour", ps.interfaceColour);
  if (ps.has(Attribute::SurfaceColour)) addScalar("surfaceColour", ps.surfaceColour);
  if (ps.has(Attribute::Dye)) addScalar("dye", ps.dye);

  grid->insertMeta("time", openvdb::DoubleMetadata(info.time));
  grid->insertMeta("frame", openvdb::Int32Metadata(info.frame));
  grid->insertMeta("scene", openvdb::StringMetadata(info.sceneName));
  grid->insertMeta("particle_spacing", openvdb::DoubleMetadata(info.particleSpacing));
  std::string names;
  for (const auto& p : info.phaseNames) names += (names.empty() ? "" : ",") + p;
  grid->insertMeta("phase_names", openvdb::StringMetadata(names));

  openvdb::MetaMap fileMeta;
  fileMeta.insertMeta(kVdbChecksumKey, openvdb::StringMetadata(vdbChecksumPlaceholder()));
  std::ostringstream os(std::ios::binary);
  openvdb::io::Stream(os).write(openvdb::GridPtrVec{grid}, fileMeta);
  std::string bytes = os.str();
  sealVdbFile(bytes);
  writeFileAtomically(path, bytes);
}

namespace {

// What the reader itself finds wrong with a file; readParticleFrame adds the path.
struct BadFrame : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class M>
auto metaValue(const openvdb::GridBase& grid, const char* key, const char* type) {
  const auto m = grid.getMetadata<M>(key);
  if (!m) throw BadFrame(fmt::format("metadata \"{}\" missing or not a {}", key, type));
  return m->value();
}

void requireAttribute(const openvdb::points::AttributeSet::Descriptor& d, const char* name, const char* type) {
  const size_t pos = d.find(name);
  if (pos == openvdb::points::AttributeSet::INVALID_POS) throw BadFrame(fmt::format("no attribute \"{}\"", name));
  if (d.valueType(pos) != type) throw BadFrame(fmt::format("attribute \"{}\" is {}, not {}", name, d.valueType(pos), type));
}

// `bytes` passed the checksum, so they are what writeParticleFrame wrote, or were made to look
// so: everything is still checked that would otherwise index out of range or allocate blindly.
ParticleFrame parseFrame(const std::string& bytes) {
  using namespace openvdb::points;
  MemoryInput buffer(bytes.data(), bytes.size());
  std::istream in(&buffer);
  // No delayed loading: it copies the bytes to a file in TMPDIR (OPENVDB_TEMP_DIR), which a crash
  // or exit leaves behind.
  openvdb::io::Stream stream(in, /*delayLoad=*/false);
  openvdb::GridPtrVecPtr grids = stream.getGrids();
  PointDataGrid::Ptr grid;
  for (auto& g : *grids)
    if (g && g->getName() == "points") grid = openvdb::gridPtrCast<PointDataGrid>(g);
  if (!grid) throw BadFrame("no point grid named \"points\"");

  ParticleFrame f;
  f.info.time = metaValue<openvdb::DoubleMetadata>(*grid, "time", "double");
  f.info.frame = metaValue<openvdb::Int32Metadata>(*grid, "frame", "int32");
  f.info.sceneName = metaValue<openvdb::StringMetadata>(*grid, "scene", "string");
  f.info.particleSpacing = metaValue<openvdb::DoubleMetadata>(*grid, "particle_spacing", "double");
  std::stringstream names(metaValue<openvdb::StringMetadata>(*grid, "phase_names", "string"));
  for (std::string s; std::getline(names, s, ',');) f.info.phaseNames.push_back(s);
  if (!std::isfinite(f.info.time) || f.info.time < 0) throw BadFrame(fmt::format("time {} is not a time", f.info.time));
  if (!std::isfinite(f.info.particleSpacing) || !(f.info.particleSpacing > 0))
    throw BadFrame(fmt::format("particle_spacing {} is not a spacing", f.info.particleSpacing));
  if (f.info.phaseNames.empty()) throw BadFrame("no phase_names");

  // Offsets and array lengths agree in every leaf (else handles would read out of bounds), and
  // the total is bounded by the file before allocating: a uniform array holds any number of
  // points in a few bytes, and the densest file the writer makes (a lattice at rest, every value
  // but P and id compressed away) has 1 byte a point.
  const auto& tree = grid->tree();
  uint64_t total = 0;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    const auto& d = leaf->attributeSet().descriptor();
    requireAttribute(d, "P", "vec3s");
    requireAttribute(d, "v", "vec3s");
    requireAttribute(d, "id", "int64");
    requireAttribute(d, "phase", "int32");
    requireAttribute(d, "pscale", "float");
    leaf->validateOffsets();
    total += leaf->pointCount();
    if (total > 64 * uint64_t(bytes.size()))
      throw BadFrame(fmt::format("{} points or more, more than its {} bytes can hold", total, bytes.size()));
  }
  auto leaf = tree.cbeginLeaf();
  if (!leaf) return f;
  const auto& descriptor = leaf->attributeSet().descriptor();
  std::vector<std::string> scalarNames;
  for (const auto& [name, pos] : descriptor.map())
    if (descriptor.valueType(pos) == "float" && name != "pscale") scalarNames.push_back(name);
  f.position.reserve(total);
  f.velocity.reserve(total);
  f.id.reserve(total);
  f.phase.reserve(total);
  f.pscale.reserve(total);
  for (const auto& s : scalarNames) f.scalars[s].reserve(total);

  for (; leaf; ++leaf) {
    AttributeHandle<openvdb::Vec3f> P(leaf->constAttributeArray("P"));
    AttributeHandle<openvdb::Vec3f> v(leaf->constAttributeArray("v"));
    AttributeHandle<int64_t> id(leaf->constAttributeArray("id"));
    AttributeHandle<int32_t> phase(leaf->constAttributeArray("phase"));
    AttributeHandle<float> pscale(leaf->constAttributeArray("pscale"));
    std::vector<std::unique_ptr<AttributeHandle<float>>> scalars;
    for (const auto& s : scalarNames) scalars.push_back(std::make_unique<AttributeHandle<float>>(leaf->constAttributeArray(s)));
    for (auto it = leaf->beginIndexOn(); it; ++it) {
      const openvdb::Vec3d world = grid->transform().indexToWorld(P.get(*it) + it.getCoord().asVec3d());
      f.position.push_back({world.x(), world.y(), world.z()});
      const auto vel = v.get(*it);
      f.velocity.push_back({vel.x(), vel.y(), vel.z()});
      f.id.push_back(id.get(*it));
      f.phase.push_back(phase.get(*it));
      f.pscale.push_back(pscale.get(*it));
      for (size_t k = 0; k < scalarNames.size(); ++k) f.scalars[scalarNames[k]].push_back(scalars[k]->get(*it));
      // The writer refuses non-finite values, and phases index phase_names.
      if (!isFinite(f.position.back()) || !isFinite(f.velocity.back()) || !std::isfinite(f.pscale.back()))
        throw BadFrame(fmt::format("particle id {} has a non-finite position, velocity or pscale", f.id.back()));
      if (f.phase.back() < 0 || size_t(f.phase.back()) >= f.info.phaseNames.size())
        throw BadFrame(fmt::format("particle id {} has phase {}, and there are {} phase_names", f.id.back(), f.phase.back(),
                                   f.info.phaseNames.size()));
    }
  }
  return f;
}

}  // namespace

ParticleFrame readParticleFrame(const std::string& path) {
  initOpenVdb();
  const std::string bytes = readSealedVdbFile(path, "particle file", "delete it and run the sim stage again");
  auto fail = [&](const std::string& why) { return std::runtime_error(path + ": not a readable particle file (" + why + ")"); };
  try {
    return parseFrame(bytes);
  } catch (const BadFrame& e) {
    throw fail(e.what());
  } catch (const openvdb::Exception& e) {
    throw fail("OpenVDB: " + shortErrorText(e.what()));
  } catch (const std::bad_alloc&) {
    throw fail("out of memory while reading it");
  } catch (const std::exception& e) {
    throw fail(shortErrorText(e.what()));
  } catch (...) {
    throw fail("unknown error");
  }
}

void checkFrameMatchesScene(const std::string& path, const FrameInfo& info, const Scene& scene) {
  // Phases (their order gives the indices in the file) and the spacing (kernel radius, voxel
  // size) decide what the particles mean. The scene name does not: --set changes spacing and
  // other physics under the same name, and a renamed copy of a scene writes the same particles.
  std::vector<std::string> names;
  for (const auto& p : scene.phases) names.push_back(p.name);
  if (info.phaseNames != names)
    throw std::runtime_error(fmt::format("{}: written by a scene with phases {}; this scene has {}", path,
                                         fmt::join(info.phaseNames, ","), fmt::join(names, ",")));
  const double s = scene.solver.particleSpacing;
  if (!(std::fabs(info.particleSpacing - s) <= 1e-9 * std::fabs(s)))
    throw std::runtime_error(fmt::format("{}: written by a scene with particle spacing {} m; this scene has {} m", path,
                                         info.particleSpacing, s));
}

}  // namespace mf
