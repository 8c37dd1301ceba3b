// Triangle meshes of level sets for DCC tools that do not ray-trace volumes: OpenVDB's
// volumeToMesh, triangulated, wound so that normals point out of the fluid, written as binary
// PLY or OBJ.
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace mf::surfacing {

struct TriangleMesh {
  std::vector<openvdb::Vec3s> vertices;
  std::vector<openvdb::Vec3I> triangles;  // counter-clockwise seen from outside
};

TriangleMesh levelSetToMesh(const openvdb::FloatGrid& levelSet);

/// Binary little-endian PLY; both written under a temporary name, then renamed.
void writePly(const std::string& path, const TriangleMesh& mesh);
void writeObj(const std::string& path, const TriangleMesh& mesh);

}  // namespace mf::surfacing
