// Triangle meshes for the ray tracer: the fluids' level sets (via surfacing's mesher) and the
// scene's solids as thick glass walls. Each mesh is closed and wound counter-clockwise seen from
// outside its material, so that the geometric normal says whether a ray enters or leaves.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "settings.h"

namespace mf::render {

struct Float3 {
  float x = 0, y = 0, z = 0;
};

struct RenderMesh {
  std::vector<Float3> positions;
  std::vector<Float3> normals;  // per vertex, unit, outward (smooth shading)
  std::vector<Float3> velocities;  // per vertex, m/s (motion vectors); empty: at rest
  std::vector<std::array<uint32_t, 3>> triangles;
  size_t size() const { return triangles.size(); }
};

class VolumeField;

/// One closed surface and what is inside it.
struct Surface {
  std::string name;
  RenderMesh mesh;
  MaterialSpec material;
  bool solid = false;  // a container or obstacle (solidSurfaces), not a fluid
  // The attribute each of the material's ramps reads (render/volume_field.h); null: no ramp.
  std::shared_ptr<const VolumeField> absorptionField = nullptr, emissionField = nullptr;
};

/// A recorded ray, to time bare traversal on exactly the rays the shader cast.
struct RecordedRay {
  float org[3], dir[3], tnear, tfar;
};

/// The zero crossing of a level set; vertex normals from the distance gradient.
RenderMesh levelSetMesh(const openvdb::FloatGrid& levelSet);

/// A container's wall of the given thickness around its fluid region (outside it), with
/// smooth normals on curved parts and sharp edges at corners.
RenderMesh solidMesh(const SolidSpec& solid, Real thickness, int segments = 128);

}  // namespace mf::render
