#include "render_frame.h"

#include <openvdb/io/File.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "path_tracer.h"

namespace fs = std::filesystem;

namespace mf::render {

RenderFrameResult renderFrame(const std::string& surfaceFile, const Scene& scene, const std::string& exrPath,
                              const std::string& pngPath, int frame, const std::function<void(int, int)>& progress) {
  RenderFrameResult result;
  if ((exrPath.empty() || fs::exists(exrPath)) && (pngPath.empty() || fs::exists(pngPath))) {
    result.skipped = true;
    return result;
  }
  const auto t0 = std::chrono::steady_clock::now();
  openvdb::initialize();
  std::vector<Surface> surfaces;
  {
    openvdb::io::File file(surfaceFile);
    file.open(false);  // grids are modified below: no delayed loading
    for (uint16_t p : scene.render.phases) {
      const std::string& name = scene.phases[p].name;
      if (!file.hasGrid(name))
        throw std::runtime_error(surfaceFile + " has no level set \"" + name + "\" (is it in surfacing.phases?)");
      auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(name));
      if (!grid) throw std::runtime_error(surfaceFile + ": grid \"" + name + "\" is not a float grid");
      // Close gaps between liquid and glass (2 voxels: about a particle radius at the default
      // voxel size), which would render as films of air.
      wetContainerWalls(*grid, scene.solids, 2.0 * grid->voxelSize()[0]);
      RenderMesh mesh = levelSetMesh(*grid);
      if (mesh.size() > 0) surfaces.push_back({name, std::move(mesh), scene.render.phaseMaterials[p]});
    }
    file.close();
  }
  for (Surface& s : solidSurfaces(scene)) surfaces.push_back(std::move(s));
  PathTracer tracer(std::move(surfaces), scene.render);
  result.triangles = tracer.triangleCount();
  result.setupSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RenderStats stats;
  const Image image = tracer.render(frame, &stats, progress);
  result.rays = stats.rays;
  result.seconds = stats.seconds;
  if (!exrPath.empty()) {
    fs::create_directories(fs::path(exrPath).parent_path());
    writeImage(exrPath, image);
  }
  if (!pngPath.empty()) {
    fs::create_directories(fs::path(pngPath).parent_path());
    writeImage(pngPath, image);
  }
  return result;
}

}  // namespace mf::render
