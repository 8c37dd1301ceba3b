#include "point_cloud.h"

#include <fmt/format.h>

#include <cstring>
#include <stdexcept>

#include "sim/file_util.h"

namespace mf::surfacing {

namespace {

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // the machines this builds for are little-endian (x86-64, arm64)
  out.append(b, sizeof(T));
}

}  // namespace

void writePointCloudPly(const std::string& path, const ParticleFrame& f) {
  const size_t n = f.size();
  for (const auto& [name, values] : f.scalars)
    if (values.size() != n) throw std::runtime_error(fmt::format("{}: attribute {} has {} values for {} particles", path, name, values.size(), n));
  std::string out = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment multifluid particles, scene {} frame {} time {}\nelement vertex {}\n"
      "property float x\nproperty float y\nproperty float z\nproperty float vx\nproperty float vy\nproperty float vz\n"
      "property double id\nproperty int phase\nproperty float pscale\n",
      f.info.sceneName, f.info.frame, f.info.time, n);
  for (const auto& [name, values] : f.scalars) out += "property float " + name + "\n";
  out += "end_header\n";
  out.reserve(out.size() + n * (40 + 4 * f.scalars.size()));
  for (size_t i = 0; i < n; ++i) {
    put(out, float(f.position[i].x)), put(out, float(f.position[i].y)), put(out, float(f.position[i].z));
    put(out, float(f.velocity[i].x)), put(out, float(f.velocity[i].y)), put(out, float(f.velocity[i].z));
    put(out, double(f.id[i]));
    put(out, int32_t(f.phase[i]));
    put(out, float(i < f.pscale.size() ? f.pscale[i] : 0.0f));
    for (const auto& [name, values] : f.scalars) put(out, values[i]);
  }
  writeFileAtomically(path, out);
}

}  // namespace mf::surfacing
