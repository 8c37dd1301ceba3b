// [surfacing] of a scene file: which phases become level sets, at what voxel size, filtered how,
// and which grids, meshes and point clouds come with them.
#include <fmt/format.h>

#include <algorithm>

#include "settings.h"
#include "sim/scene_reader.h"

namespace mf {

using scene_reading::Reader;
using scene_reading::TableReader;

SurfacingSettings readSurfacingSettings(scene_reading::SceneDocument& doc, const Scene& scene) {
  Reader& r = doc.reader;
  TableReader t(r, doc.stageTable("surfacing"), "surfacing");
  SurfacingSettings o;
  if (!t.phaseNames("phases", scene, o.phases, [](int) { return std::string(); }))
    for (size_t k = 0; k < scene.phases.size(); ++k) o.phases.push_back(uint16_t(k));
  o.voxelRatio = t.number("voxel_ratio", o.voxelRatio, 0.05, 2, "of the particle spacing");
  o.radiusRatio = t.number("radius_ratio", o.radiusRatio, 0.3, 3, "of the particle spacing");
  o.searchRatio = t.number("search_ratio", o.searchRatio, 0.5, 6, "of the particle spacing");
  if (o.searchRatio < o.radiusRatio) r.problem(t.node("search_ratio"), "surfacing.search_ratio", "must be at least surfacing.radius_ratio");
  o.filterRadius = t.integer("filter_radius", o.filterRadius, 0, 5, "voxels");
  o.filterSpatialSigma = t.number("filter_spatial_sigma", o.filterSpatialSigma, 0, 5, "voxels", true);
  o.filterRangeSigma = t.number("filter_range_sigma", o.filterRangeSigma, 0, 10, "voxels (0 = plain Gaussian)");
  o.filterIterations = t.integer("filter_iterations", o.filterIterations, 0, 20);
  o.clipToSolids = t.boolean("clip_to_solids", o.clipToSolids);
  o.wetWalls = t.boolean("wet_walls", o.wetWalls);
  o.fog = t.boolean("fog", o.fog);
  o.velocity = t.boolean("velocity", o.velocity);
  o.pointsPly = t.boolean("points_ply", o.pointsPly);
  t.strings("attributes", "\"temperature\" and/or \"dye\"", [&](const toml::node& e, const std::string& a) {
    if (a != "temperature" && a != "dye") r.problem(&e, "surfacing.attributes", "\"" + a + "\" is not one of \"temperature\", \"dye\"");
    else if (std::find(o.attributes.begin(), o.attributes.end(), a) != o.attributes.end())
      r.problem(&e, "surfacing.attributes", "\"" + a + "\" is listed twice");
    else o.attributes.push_back(a);
  });
  t.strings("meshes", "\"ply\" and/or \"obj\"", [&](const toml::node& e, const std::string& m) {
    if (m == "ply") o.meshPly = true;
    else if (m == "obj") o.meshObj = true;
    else r.problem(&e, "surfacing.meshes", "\"" + m + "\" is not one of \"ply\", \"obj\"");
  });
  return o;
}

}  // namespace mf
