#include "surface_frame.h"

#include <fmt/format.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <filesystem>
#include <sstream>

#include "attribute_grid.h"
#include "container_walls.h"
#include "fluid_interfaces.h"
#include "mesh_io.h"
#include "particle_surface.h"
#include "periodic_images.h"
#include "sim/file_util.h"
#include "sim/particle_io.h"
#include "point_cloud.h"
#include "sim/vdb_file.h"

namespace fs = std::filesystem;

namespace mf::surfacing {

SurfaceFrameResult surfaceFrame(const std::string& particleFile, const Scene& scene, const SurfacingSettings& s,
                                const std::string& surfaceFile, const std::string& meshDir, int frame) {
  SurfaceFrameResult result;
  auto meshPath = [&](const std::string& phase, const char* ext) {
    return (fs::path(meshDir) / fmt::format("{}.{:04d}.{}", phase, frame, ext)).string();
  };
  // Beside the meshes' folder: DIR/points/points.NNNN.ply (a phase may be called "points").
  const std::string pointsFile = (fs::path(meshDir).parent_path() / "points" / fmt::format("points.{:04d}.ply", frame)).string();
  bool complete = fs::exists(surfaceFile) && (!s.pointsPly || fs::exists(pointsFile));
  for (uint16_t p : s.phases) {
    if (s.meshPly) complete &= fs::exists(meshPath(scene.phases[p].name, "ply"));
    if (s.meshObj) complete &= fs::exists(meshPath(scene.phases[p].name, "obj"));
  }
  if (complete) {
    result.skipped = true;
    return result;
  }

  const ParticleFrame particles = readParticleFrame(particleFile);
  checkFrameMatchesScene(particleFile, particles.info, scene);
  if (s.pointsPly) {
    fs::create_directories(fs::path(pointsFile).parent_path());
    writePointCloudPly(pointsFile, particles);
    result.written.push_back(pointsFile);
  }
  const double spacing = particles.info.particleSpacing;  // the scene's, to 1e-9 (checked)
  // Each fluid's level set first: where two fluids touch, their films are closed together.
  const PeriodicDomain periodic = scene.periodic();
  struct Fluid {
    std::vector<openvdb::Vec3d> positions;  // with the periodic images
    std::vector<uint32_t> imageSource;      // per image, the index of its particle
    ParticleSurface surface;
  };
  std::vector<Fluid> fluids(s.phases.size());
  for (size_t f = 0; f < s.phases.size(); ++f) {
    const uint16_t p = s.phases[f];
    Fluid& fluid = fluids[f];
    std::vector<openvdb::Vec3f> velocities;
    for (size_t i = 0; i < particles.size(); ++i)
      if (particles.phase[i] == p) {
        fluid.positions.emplace_back(particles.position[i].x, particles.position[i].y, particles.position[i].z);
        if (s.velocity)
          velocities.emplace_back(float(particles.velocity[i].x), float(particles.velocity[i].y), float(particles.velocity[i].z));
      }
    // Periodic faces: images as far as the kernel and the filter reach (then cut flat there).
    std::vector<openvdb::Vec3d> images;
    fluid.imageSource = periodicImages(fluid.positions, periodic,
                                       spacing * (s.searchRatio + s.voxelRatio * (s.filterRadius * s.filterIterations + 3)), images);
    fluid.positions.insert(fluid.positions.end(), images.begin(), images.end());
    if (!velocities.empty()) {
      velocities.reserve(fluid.positions.size());
      for (uint32_t k : fluid.imageSource) velocities.push_back(velocities[k]);
    }
    fluid.surface = particlesToSurface(fluid.positions, velocities, spacing, s);
    cutAtPeriodicFaces(*fluid.surface.levelSet, periodic);
  }
  {
    std::vector<openvdb::FloatGrid::Ptr> levelSets;
    for (const Fluid& fluid : fluids) levelSets.push_back(fluid.surface.levelSet);
    if (fluidBandsTouch(levelSets)) {
      std::vector<openvdb::Vec3d> all;
      for (const Fluid& fluid : fluids) all.insert(all.end(), fluid.positions.begin(), fluid.positions.end());
      const openvdb::FloatGrid::Ptr united = particlesToSurface(all, {}, spacing, s).levelSet;
      cutAtPeriodicFaces(*united, periodic);
      result.interfaceVoxels = closeFluidInterfaces(levelSets, *united, float(kInterfaceOverlapVoxels * s.voxelRatio * spacing));
      for (size_t f = 0; f < fluids.size(); ++f) fluids[f].surface.levelSet = levelSets[f];
    }
  }

  openvdb::GridPtrVec grids;
  bool firstFog = true, firstVel = true;
  for (size_t f = 0; f < s.phases.size(); ++f) {
    const uint16_t p = s.phases[f];
    const std::string& name = scene.phases[p].name;
    const std::vector<openvdb::Vec3d>& positions = fluids[f].positions;
    ParticleSurface& surface = fluids[f].surface;
    if (s.clipToSolids) clipToSolids(*surface.levelSet, scene.solids, s.searchRatio * spacing);
    if (s.wetWalls && !s.wallThickness.empty()) {
      std::vector<double> depths;
      for (double t : s.wallThickness) depths.push_back(wettingDepth(surface.levelSet->voxelSize()[0], t));
      wetContainerWalls(*surface.levelSet, scene.solids, depths);
    }
    surface.levelSet->setName(name);
    surface.levelSet->insertMeta("time", openvdb::DoubleMetadata(particles.info.time));
    surface.levelSet->insertMeta("frame", openvdb::Int32Metadata(frame));
    result.activeVoxels += surface.levelSet->activeVoxelCount();
    grids.push_back(surface.levelSet);
    if (s.fog) {
      // Blender and Houdini look for "density"; further phases get their own name.
      auto fog = surface.levelSet->deepCopy();
      openvdb::tools::sdfToFogVolume(*fog);
      fog->setName(firstFog ? std::string("density") : "density_" + name);
      firstFog = false;
      grids.push_back(fog);
    }
    for (const std::string& attr : s.attributes) {
      const auto found = particles.scalars.find(attr);
      if (found == particles.scalars.end())
        throw std::runtime_error(fmt::format("{}: no particle attribute \"{}\" for surfacing.attributes (the scene's particles carry no {})",
                                             particleFile, attr, attr));
      std::vector<float> values;
      for (size_t i = 0; i < particles.size(); ++i)
        if (particles.phase[i] == p) values.push_back(found->second[i]);
      values.reserve(values.size() + fluids[f].imageSource.size());
      for (uint32_t k : fluids[f].imageSource) values.push_back(values[k]);
      auto grid = attributeGrid(positions, values, 2 * spacing, surface.levelSet->transform());
      grid->setName(attr + "_" + name);
      grid->insertMeta("time", openvdb::DoubleMetadata(particles.info.time));
      grid->insertMeta("frame", openvdb::Int32Metadata(frame));
      grids.push_back(grid);
    }
    if (surface.velocity) {
      surface.velocity->setName(firstVel ? std::string("vel") : "vel_" + name);
      firstVel = false;
      surface.velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
      surface.velocity->insertMeta("fluid", openvdb::StringMetadata(name));  // "vel" names no fluid
      grids.push_back(surface.velocity);
    }
    if (s.meshPly || s.meshObj) {
      fs::create_directories(meshDir);
      TriangleMesh mesh = levelSetToMesh(*surface.levelSet);
      if (s.meshPly && surface.velocity) sampleVertexVelocities(mesh, *surface.velocity);
      if (s.meshPly) {
        writePly(meshPath(name, "ply"), mesh);
        result.written.push_back(meshPath(name, "ply"));
      }
      if (s.meshObj) {
        writeObj(meshPath(name, "obj"), mesh);
        result.written.push_back(meshPath(name, "obj"));
      }
    }
  }
  openvdb::MetaMap fileMeta;
  fileMeta.insertMeta(kVdbChecksumKey, openvdb::StringMetadata(vdbChecksumPlaceholder()));
  std::ostringstream os(std::ios::binary);
  openvdb::io::Stream(os).write(grids, fileMeta);
  std::string bytes = os.str();
  sealVdbFile(bytes);
  fs::create_directories(fs::path(surfaceFile).parent_path());
  writeFileAtomically(surfaceFile, bytes);  // last: its presence marks the frame complete
  result.written.push_back(surfaceFile);
  return result;
}

}  // namespace mf::surfacing
