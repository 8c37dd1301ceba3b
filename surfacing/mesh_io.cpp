#include "mesh_io.h"

#include <fmt/format.h>
#include <openvdb/tools/GridOperators.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <sstream>
#include <stdexcept>

#include "sim/file_util.h"

namespace mf::surfacing {

TriangleMesh levelSetToMesh(const openvdb::FloatGrid& grid) {
  TriangleMesh mesh;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, mesh.vertices, mesh.triangles, quads, 0.0);
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  // Orient by the distance gradient (which points out of the fluid), whatever winding the
  // mesher used: sample it at the first face that gives a clear answer.
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(grid);
  for (const auto& t : mesh.triangles) {
    const openvdb::Vec3d a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const openvdb::Vec3d n = (b - a).cross(c - a);
    if (n.length() == 0) continue;
    const openvdb::Vec3d centre = (a + b + c) / 3.0;
    const double h = grid.voxelSize()[0] * 0.5;
    const openvdb::Vec3d unit = n.unit();
    const double outward = sampler.wsSample(centre + unit * h) - sampler.wsSample(centre - unit * h);
    if (outward == 0) continue;
    if (outward < 0)
      for (auto& f : mesh.triangles) std::swap(f[1], f[2]);
    break;
  }
  return mesh;
}

void sampleVertexVelocities(TriangleMesh& mesh, const openvdb::Vec3SGrid& velocity) {
  openvdb::tools::GridSampler<openvdb::Vec3SGrid, openvdb::tools::BoxSampler> sampler(velocity);
  mesh.velocities.clear();
  mesh.velocities.reserve(mesh.vertices.size());
  for (const auto& p : mesh.vertices) mesh.velocities.push_back(sampler.wsSample(openvdb::Vec3d(p)));
}

void writePly(const std::string& path, const TriangleMesh& mesh) {
  const bool moving = !mesh.velocities.empty();
  if (moving && mesh.velocities.size() != mesh.vertices.size())
    throw std::logic_error(fmt::format("{}: {} velocities for {} vertices", path, mesh.velocities.size(), mesh.vertices.size()));
  std::ostringstream os(std::ios::binary);
  os << "ply\nformat binary_little_endian 1.0\ncomment multifluid level set mesh\n"
     << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
     << (moving ? "property float vx\nproperty float vy\nproperty float vz\n" : "")
     << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t k = 0; k < mesh.vertices.size(); ++k) {
    os.write(reinterpret_cast<const char*>(mesh.vertices[k].asPointer()), 12);
    if (moving) os.write(reinterpret_cast<const char*>(mesh.velocities[k].asPointer()), 12);
  }
  for (const auto& t : mesh.triangles) {
    const unsigned char three = 3;
    os.write(reinterpret_cast<const char*>(&three), 1);
    const int32_t idx[3] = {int32_t(t[0]), int32_t(t[1]), int32_t(t[2])};
    os.write(reinterpret_cast<const char*>(idx), 12);
  }
  writeFileAtomically(path, os.str());
}

void writeObj(const std::string& path, const TriangleMesh& mesh) {
  std::string s = "# multifluid level set mesh\n";
  s.reserve(mesh.vertices.size() * 40 + mesh.triangles.size() * 30);
  for (const auto& v : mesh.vertices) s += fmt::format("v {:.7g} {:.7g} {:.7g}\n", v.x(), v.y(), v.z());
  for (const auto& t : mesh.triangles) s += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  writeFileAtomically(path, s);
}

}  // namespace mf::surfacing
