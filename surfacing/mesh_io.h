// Triangle meshes of level sets for DCC tools that do not ray-trace volumes: OpenVDB's
// volumeToMesh, triangulated, wound so that normals point out of the fluid, written as binary
// PLY or OBJ. A PLY carries each vertex's velocity (vx, vy, vz) when the fluid has a velocity
// grid: Blender's Cycles blurs a mesh by its "velocity" attribute, so a mesh sequence whose
// topology changes every frame still gets motion blur.
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace mf::surfacing {

struct TriangleMesh {
  std::vector<openvdb::Vec3s> vertices;
  std::vector<openvdb::Vec3I> triangles;  // counter-clockwise seen from outside
  std::vector<openvdb::Vec3s> velocities; // per vertex, m/s; empty: none
};

TriangleMesh levelSetToMesh(const openvdb::FloatGrid& levelSet);

/// Sets mesh.velocities from `velocity` (trilinear, as the renderer samples it for motion blur).
void sampleVertexVelocities(TriangleMesh& mesh, const openvdb::Vec3SGrid& velocity);

/// Binary little-endian PLY (with vx, vy, vz when the mesh has velocities; OBJ has no place for
/// them); both written under a temporary name, then renamed.
void writePly(const std::string& path, const TriangleMesh& mesh);
void writeObj(const std::string& path, const TriangleMesh& mesh);

}  // namespace mf::surfacing
