// The surfacing stage's settings: what the [surfacing] table of a scene file asks of the level
// sets, meshes and grids made from each frame's particles. Read by settings_file.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene.h"

namespace mf {

/// What the surfacing stage makes of the particles: the scene file's [surfacing] table.
struct SurfacingSettings {
  std::vector<uint16_t> phases;    // phases to surface; empty in the file means all
  Real voxelRatio = 0.5;           // voxel size / particle spacing
  Real radiusRatio = 0.6;          // Zhu & Bridson particle radius / particle spacing
  Real searchRatio = 1.5;          // Zhu & Bridson kernel radius / particle spacing
  int filterRadius = 3;            // bilateral stencil radius, voxels
  Real filterSpatialSigma = 2.0;   // voxels
  Real filterRangeSigma = 2.0;     // voxels of distance
  int filterIterations = 4;
  bool clipToSolids = true;        // cut each level set where it overlaps a container's walls
  bool wetWalls = true;            // extend liquid into the walls the render draws (container_walls.h)
  // Per solid, the thickness of the wall the render draws (0: not drawn), which bounds how far
  // the liquid reaches into it: from [render], filled in by the pipeline (parseSceneStages).
  std::vector<double> wallThickness;
  bool fog = false;                // also a fog-volume copy ("density")
  bool velocity = false;           // also a velocity grid ("vel") from the particles
  bool meshPly = false, meshObj = false;
  bool pointsPly = false;          // also the particles as a PLY point cloud (points/points.NNNN.ply)
  std::vector<std::string> attributes;  // per phase a grid "<attribute>_<phase>": "temperature", "dye"
};

namespace scene_reading {
struct SceneDocument;
}

/// The [surfacing] table of a scene file, after its simulation part (it names phases); every
/// problem goes to doc.reader (sim/scene_reader.h).
SurfacingSettings readSurfacingSettings(scene_reading::SceneDocument& doc, const Scene& scene);

}  // namespace mf
