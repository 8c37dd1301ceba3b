// Per-frame particle files as OpenVDB point data (Houdini, Blender and OpenVDB's own tools read
// them): one PointDataGrid "points" with P, v (m/s), id (int64), pscale (m, half the particle
// spacing), phase (int32), density and pressure, plus each optional attribute the scene has
// (temperature, interfaceColour, surfaceColour). Grid metadata: time, frame, scene, phase names,
// particle spacing; file metadata: a checksum of the file (vdb_file.h). OpenVDB headers stay in
// the .cpp (compile time).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "particles.h"
#include "scene.h"

namespace mf {

struct FrameInfo {
  int frame = 0;
  double time = 0;
  std::string sceneName;
  std::vector<std::string> phaseNames;
  double particleSpacing = 0;
};

/// A frame's metadata for `scene`: its name, phase names and particle spacing.
FrameInfo frameInfoFor(const Scene& scene, int frame = 0, double time = 0);

/// Writes `path` under a temporary name, then renames it. The file bytes depend only on the
/// particle data (OpenVDB's random file UUID is replaced by one derived from the content).
void writeParticleFrame(const std::string& path, const ParticleSet& particles, const FrameInfo& info);

/// A frame read back, in file order (OpenVDB orders points by voxel).
struct ParticleFrame {
  FrameInfo info;
  std::vector<Vec3> position, velocity;
  std::vector<int64_t> id;
  std::vector<int32_t> phase;
  std::vector<float> pscale;
  std::map<std::string, std::vector<float>> scalars;  // density, pressure, temperature, ...
  size_t size() const { return id.size(); }
};

/// Checks the file's size and checksum before parsing, then its metadata, attributes and
/// offsets. Every failure is a std::runtime_error "<path>: not a readable particle file (...)".
ParticleFrame readParticleFrame(const std::string& path);

/// Throws std::runtime_error naming `path`, the field and both values unless the frame was
/// written by a scene with the same phases, in the same order, and particle spacing as `scene`.
void checkFrameMatchesScene(const std::string& path, const FrameInfo& info, const Scene& scene);

}  // namespace mf
