#include "render_frame.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "aov.h"
#include "camera.h"
#include "denoise.h"
#include "path_tracer.h"
#include "volume_field.h"
#include "sim/vdb_file.h"

namespace fs = std::filesystem;

namespace mf::render {

namespace {

struct BadSurface : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The level set of each phase in settings.phases, checked: a FloatGrid level set of that
// name with uniform, finite voxels; and the attribute grids its material's ramps read. Every
// failure names the file.
struct FluidGrids {
  uint16_t phase;
  openvdb::FloatGrid::Ptr levelSet, absorption, emission;  // the ramps' attribute grids, or null
  openvdb::Vec3SGrid::Ptr velocity;                         // surfacing.velocity's, or null
};

std::vector<FluidGrids> readLevelSets(const std::string& path, const Scene& scene, const RenderSettings& settings) {
  const std::string bytes = readSealedVdbFile(path, "surface file", "delete it and run the surface stage again");
  std::vector<FluidGrids> out;
  try {
    MemoryInput buffer(bytes.data(), bytes.size());
    std::istream in(&buffer);
    // Not io::File: with delayed loading it copies files to TMPDIR (OPENVDB_TEMP_DIR), and the
    // bytes parsed are the ones whose checksum was checked.
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    const openvdb::GridPtrVecPtr grids = stream.getGrids();
    for (uint16_t p : settings.phases) {
      const std::string& name = scene.phases[p].name;
      openvdb::GridBase::Ptr found;
      for (const auto& g : *grids)
        if (g && g->getName() == name) found = g;
      if (!found) throw BadSurface("no level set \"" + name + "\" (is it in surfacing.phases?)");
      auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(found);
      if (!grid) throw BadSurface("grid \"" + name + "\" is a " + found->type() + ", not a float grid");
      if (grid->getGridClass() != openvdb::GRID_LEVEL_SET) throw BadSurface("grid \"" + name + "\" is not a level set");
      const double voxel = grid->voxelSize()[0];
      if (!grid->hasUniformVoxels() || !std::isfinite(voxel) || !(voxel > 0))
        throw BadSurface("grid \"" + name + "\" has no uniform, finite voxel size");
      FluidGrids fluid{p, grid, nullptr, nullptr, nullptr};
      for (const auto& g : *grids)
        if (auto v = openvdb::gridPtrCast<openvdb::Vec3SGrid>(g))
          if (const auto m = v->getMetadata<openvdb::StringMetadata>("fluid"); m && m->value() == name) fluid.velocity = v;
      // The attribute grids its material's ramps read (surfacing.attributes writes them).
      const MaterialSpec& m = settings.phaseMaterials[p];
      for (auto [ramp, field] : {std::pair{&m.absorptionRamp, &fluid.absorption}, std::pair{&m.emissionRamp, &fluid.emission}}) {
        if (ramp->empty()) continue;
        const std::string attr = ramp->attribute + "_" + name;
        openvdb::FloatGrid::Ptr a;
        for (const auto& g : *grids)
          if (g && g->getName() == attr) a = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
        if (!a)
          throw BadSurface("no float grid \"" + attr + "\" for the material's ramp (surfacing.attributes must list \"" +
                           ramp->attribute + "\" when the frame is surfaced: delete the surface frames made without it)");
        *field = a;
      }
      out.push_back(fluid);
    }
  } catch (const BadSurface& e) {
    throw std::runtime_error(path + ": " + e.what());
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(path + ": not a readable surface file (out of memory while reading it)");
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": not a readable surface file (" + shortErrorText(e.what()) + ")");
  } catch (...) {
    throw std::runtime_error(path + ": not a readable surface file (unknown error)");
  }
  return out;
}

}  // namespace

RenderFrameResult renderFrame(const std::string& surfaceFile, const Scene& scene, const RenderSettings& settings,
                              const std::string& exrPath, const std::string& pngPath, int frame,
                              const std::function<void(int, int)>& progress) {
  RenderFrameResult result;
  const bool coverageOnly = exrPath.empty() && pngPath.empty();
  if (!coverageOnly && (exrPath.empty() || fs::exists(exrPath)) && (pngPath.empty() || fs::exists(pngPath))) {
    result.skipped = true;
    return result;
  }
  const auto t0 = std::chrono::steady_clock::now();
  openvdb::initialize();
  std::vector<Surface> surfaces;
  for (FluidGrids& f : readLevelSets(surfaceFile, scene, settings)) {
    const openvdb::FloatGrid& grid = *f.levelSet;
    RenderMesh mesh = levelSetMesh(grid);
    if (mesh.size() == 0) continue;
    if (f.velocity) {  // per vertex, for the motion vectors
      openvdb::tools::GridSampler<openvdb::Vec3SGrid, openvdb::tools::BoxSampler> sampler(*f.velocity);
      for (const Float3& p : mesh.positions) {
        const openvdb::Vec3s v = sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z));
        mesh.velocities.push_back({v.x(), v.y(), v.z()});
      }
    }
    Surface s{scene.phases[f.phase].name, std::move(mesh), settings.phaseMaterials[f.phase]};
    try {
      if (f.absorption) s.absorptionField = std::make_shared<VolumeField>(*f.absorption);
      if (f.emission) s.emissionField = std::make_shared<VolumeField>(*f.emission);
    } catch (const std::exception& e) {
      throw std::runtime_error(surfaceFile + ": " + e.what());
    }
    surfaces.push_back(std::move(s));
  }
  result.anyFluid = !surfaces.empty();
  for (Surface& s : solidSurfaces(scene, settings)) surfaces.push_back(std::move(s));
  PathTracer tracer(std::move(surfaces), atTime(settings, frame / scene.frameRate), 1 / scene.frameRate);
  tracer.setNextFrame(atTime(settings, (frame + 1) / scene.frameRate), 1 / scene.frameRate);
  result.triangles = tracer.triangleCount();
  result.setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Solids are glass to see through: what counts is a fluid's surface behind them.
  result.fluidCoverage = tracer.coverage([](const Surface& s) { return !s.solid; });
  if (coverageOnly) return result;
  RenderStats stats;
  Aovs aovs;
  const Image noisy = tracer.render(frame, &stats, progress, nullptr, &aovs);
  result.rays = stats.rays;
  result.seconds = stats.seconds;
  Image image = noisy;
  if (settings.denoise) {
    const auto td = std::chrono::steady_clock::now();
    DenoiseSettings ds;
    ds.iterations = settings.denoiseIterations;
    image = denoise(noisy, aovs, ds);
    result.denoiseSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - td).count();
  }
  if (!exrPath.empty()) {
    fs::create_directories(fs::path(exrPath).parent_path());
    writeFrameExr(exrPath, image, settings.denoise ? &noisy : nullptr, aovs);
  }
  if (!pngPath.empty()) {
    fs::create_directories(fs::path(pngPath).parent_path());
    writeImage(pngPath, image);
  }
  return result;
}

}  // namespace mf::render
