#include "particle_io.h"

#include <fmt/format.h>
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

namespace mf {

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
  addScalar("pressure", ps.pressure);
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

  std::ostringstream os(std::ios::binary);
  openvdb::io::Stream(os).write(openvdb::GridPtrVec{grid});
  std::string bytes = os.str();
  makeVdbUuidDeterministic(bytes);
  writeFileAtomically(path, bytes);
}

ParticleFrame readParticleFrame(const std::string& path) {
  initOpenVdb();
  using namespace openvdb::points;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  openvdb::io::Stream stream(in);
  openvdb::GridPtrVecPtr grids = stream.getGrids();
  PointDataGrid::Ptr grid;
  for (auto& g : *grids)
    if (g->getName() == "points") grid = openvdb::gridPtrCast<PointDataGrid>(g);
  if (!grid) throw std::runtime_error(path + ": no point grid named \"points\"");

  ParticleFrame f;
  f.info.time = grid->metaValue<double>("time");
  f.info.frame = grid->metaValue<int32_t>("frame");
  f.info.sceneName = grid->metaValue<std::string>("scene");
  f.info.particleSpacing = grid->metaValue<double>("particle_spacing");
  std::stringstream names(grid->metaValue<std::string>("phase_names"));
  for (std::string s; std::getline(names, s, ',');) f.info.phaseNames.push_back(s);

  const auto& tree = grid->tree();
  auto leaf = tree.cbeginLeaf();
  if (!leaf) return f;
  const auto& descriptor = leaf->attributeSet().descriptor();
  std::vector<std::string> scalarNames;
  for (const auto& [name, pos] : descriptor.map())
    if (descriptor.type(pos).first == "float" && name != "pscale") scalarNames.push_back(name);

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
    }
  }
  return f;
}

}  // namespace mf
