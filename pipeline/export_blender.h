// `multifluid export blender DIR`: a .blend of a run folder, built by Debian's Blender in
// background mode with the script pipeline/blender/build_blend.py, from a JSON manifest of the
// run that this side resolves (the scene as run, its camera as the renderer frames it, the
// finished surface frames).
#pragma once

#include <string>

namespace mf::pipeline {

struct BlenderExportOptions {
  std::string runDir;
  std::string out;              // the .blend; "" = DIR/<scene>.blend
  std::string meshes = "vdb";   // "vdb": level sets + Volume to Mesh; "ply": the run's PLY meshes
  double timeoutSeconds = 1800; // Blender is stopped past this
};

/// Writes the manifest (out + ".json"), runs Blender, and renames its .blend into place only when
/// it exited 0 and wrote the file. Throws std::runtime_error with what to do (no blender on PATH,
/// not a run folder, no finished surface frames, Blender failed: its log's tail).
int exportBlender(const BlenderExportOptions& options);

/// Where build_blend.py is: in the source tree this binary was built from (compiled in by CMake).
std::string blenderScriptPath();

}  // namespace mf::pipeline
