#include "geometry.h"

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

#include "sim/solids.h"
#include "surfacing/mesh_io.h"

namespace mf::render {

namespace {

Float3 toFloat3(const Vec3& v) { return {float(v.x), float(v.y), float(v.z)}; }
Vec3 toVec3(const Float3& v) { return {v.x, v.y, v.z}; }

/// Appends a triangle, wound so that its geometric normal agrees with `outward`.
void addTriangle(RenderMesh& m, uint32_t a, uint32_t b, uint32_t c, const Vec3& outward) {
  const Vec3 pa = toVec3(m.positions[a]), pb = toVec3(m.positions[b]), pc = toVec3(m.positions[c]);
  const Vec3 n = cross(pb - pa, pc - pa);
  if (lengthSquared(n) == 0) return;  // degenerate (on the axis of a lathe)
  if (dot(n, outward) >= 0) m.triangles.push_back({a, b, c});
  else m.triangles.push_back({a, c, b});
}

/// A planar quad with one flat normal.
void addQuad(RenderMesh& m, const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& outward) {
  const uint32_t base = uint32_t(m.positions.size());
  for (const Vec3& p : {p0, p1, p2, p3}) {
    m.positions.push_back(toFloat3(p));
    m.normals.push_back(toFloat3(outward));
  }
  addTriangle(m, base, base + 1, base + 2, outward);
  addTriangle(m, base, base + 2, base + 3, outward);
}

/// The six faces of [lo, hi] (without the top if `openTop`), normals outward times `sign`.
void addBox(RenderMesh& m, const Vec3& lo, const Vec3& hi, bool openTop, Real sign) {
  auto corner = [&](int i) { return Vec3{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z}; };
  // Faces as corner indices (bits x, y, z) and their outward normals.
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  const Vec3 normals[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (int f = 0; f < 6; ++f) {
    if (openTop && f == 3) continue;
    addQuad(m, corner(faces[f][0]), corner(faces[f][1]), corner(faces[f][2]), corner(faces[f][3]), normals[f] * sign);
  }
}

/// Rotates a closed polygon in the (r, y) half-plane, counter-clockwise, about the +y axis
/// through `base`. Each edge gets its own ring of vertices; neighbouring edges share smoothed
/// normals where they meet at less than 30 degrees, so curved walls look round and rims sharp.
void addLathe(RenderMesh& m, const Vec3& base, const std::vector<std::pair<Real, Real>>& polygonRY, int segments) {
  const size_t n = polygonRY.size();
  std::vector<std::pair<Real, Real>> edgeNormal(n);  // (n_r, n_y) of edge k -> k+1
  for (size_t k = 0; k < n; ++k) {
    const auto [r0, y0] = polygonRY[k];
    const auto [r1, y1] = polygonRY[(k + 1) % n];
    const Real dr = r1 - r0, dy = y1 - y0, len = std::hypot(dr, dy);
    edgeNormal[k] = len > 0 ? std::make_pair(dy / len, -dr / len) : std::make_pair(0.0, 0.0);
  }
  auto vertexNormal = [&](size_t edge, size_t vertex) {
    const size_t other = vertex == edge ? (edge + n - 1) % n : (edge + 1) % n;
    const auto a = edgeNormal[edge], b = edgeNormal[other];
    if (a.first * b.first + a.second * b.second > std::cos(30.0 * M_PI / 180.0)) {
      const Real r = a.first + b.first, y = a.second + b.second, l = std::hypot(r, y);
      return std::make_pair(r / l, y / l);
    }
    return a;
  };
  for (size_t k = 0; k < n; ++k) {
    const size_t k1 = (k + 1) % n;
    if (polygonRY[k].first == 0 && polygonRY[k1].first == 0) continue;  // on the axis
    const auto n0 = vertexNormal(k, k), n1 = vertexNormal(k, k1);
    const uint32_t first = uint32_t(m.positions.size());
    for (int s = 0; s <= segments; ++s) {
      const Real phi = 2 * M_PI * (s % segments) / segments, c = std::cos(phi), sn = std::sin(phi);
      for (int e = 0; e < 2; ++e) {
        const auto [r, y] = polygonRY[e ? k1 : k];
        const auto nn = e ? n1 : n0;
        m.positions.push_back(toFloat3(base + Vec3{r * c, y, r * sn}));
        m.normals.push_back(toFloat3(Vec3{nn.first * c, nn.second, nn.first * sn}));
      }
    }
    for (int s = 0; s < segments; ++s) {
      const uint32_t a = first + 2 * s, b = a + 1, c = a + 2, d = a + 3;
      // The face normal at this segment, from the edge normal rotated to its mid angle.
      const Real phi = 2 * M_PI * (s + 0.5) / segments;
      const Vec3 out{edgeNormal[k].first * std::cos(phi), edgeNormal[k].second, edgeNormal[k].first * std::sin(phi)};
      addTriangle(m, a, b, d, out);
      addTriangle(m, a, d, c, out);
    }
  }
}

}  // namespace

RenderMesh levelSetMesh(const openvdb::FloatGrid& levelSet) {
  const surfacing::TriangleMesh mesh = surfacing::levelSetToMesh(levelSet);
  RenderMesh m;
  m.positions.reserve(mesh.vertices.size());
  m.normals.reserve(mesh.vertices.size());
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi(levelSet);
  const double h = 0.5 * levelSet.voxelSize()[0];
  for (const auto& v : mesh.vertices) {
    m.positions.push_back({v.x(), v.y(), v.z()});
    const openvdb::Vec3d p(v);
    // Central differences of the distance: it points out of the fluid.
    openvdb::Vec3d g(phi.wsSample(p + openvdb::Vec3d(h, 0, 0)) - phi.wsSample(p - openvdb::Vec3d(h, 0, 0)),
                     phi.wsSample(p + openvdb::Vec3d(0, h, 0)) - phi.wsSample(p - openvdb::Vec3d(0, h, 0)),
                     phi.wsSample(p + openvdb::Vec3d(0, 0, h)) - phi.wsSample(p - openvdb::Vec3d(0, 0, h)));
    const double l = g.length();
    g = l > 0 ? g / l : openvdb::Vec3d(0, 1, 0);
    m.normals.push_back({float(g.x()), float(g.y()), float(g.z())});
  }
  m.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) m.triangles.push_back({t[0], t[1], t[2]});
  return m;
}

RenderMesh solidMesh(const SolidSpec& s, Real t, int segments) {
  RenderMesh m;
  switch (s.shape) {
    case SolidSpec::Shape::Box: {
      const Vec3 grow{t, t, t};
      Vec3 outerHi = s.max + grow;
      if (s.openTop) outerHi.y = s.max.y;
      addBox(m, s.min - grow, outerHi, s.openTop, 1);
      addBox(m, s.min, s.max, s.openTop, -1);  // the inner wall faces the fluid
      if (s.openTop) {                         // the rim between the two
        const Real y = s.max.y;
        const Vec3 up{0, 1, 0};
        const Vec3 oLo = s.min - grow, oHi = s.max + grow;
        addQuad(m, {oLo.x, y, oLo.z}, {oHi.x, y, oLo.z}, {s.max.x, y, s.min.z}, {s.min.x, y, s.min.z}, up);
        addQuad(m, {oHi.x, y, oLo.z}, {oHi.x, y, oHi.z}, {s.max.x, y, s.max.z}, {s.max.x, y, s.min.z}, up);
        addQuad(m, {oHi.x, y, oHi.z}, {oLo.x, y, oHi.z}, {s.min.x, y, s.max.z}, {s.max.x, y, s.max.z}, up);
        addQuad(m, {oLo.x, y, oHi.z}, {oLo.x, y, oLo.z}, {s.min.x, y, s.min.z}, {s.min.x, y, s.max.z}, up);
      }
      break;
    }
    case SolidSpec::Shape::Cylinder:
    case SolidSpec::Shape::Revolution: {
      // The wall's cross-section as a counter-clockwise polygon in (r, y): outside up, inside down.
      std::vector<std::pair<Real, Real>> profile;  // inner (r, y) from bottom to top
      if (s.shape == SolidSpec::Shape::Cylinder) profile = {{s.radius, 0}, {s.radius, s.height}};
      else
        for (const auto& [y, r] : s.profile) profile.push_back({r, y});
      const Real yBottom = profile.front().second, yTop = profile.back().second;
      std::vector<std::pair<Real, Real>> poly;
      poly.push_back({0, yBottom - t});
      for (const auto& [r, y] : profile) poly.push_back({r + t, y == yBottom ? yBottom - t : y});
      if (s.openTop) {
        poly.back().second = yTop;
      } else {
        poly.back().second = yTop + t;
        poly.push_back({0, yTop + t});
        poly.push_back({0, yTop});
      }
      for (auto it = profile.rbegin(); it != profile.rend(); ++it) poly.push_back(*it);
      poly.push_back({0, yBottom});
      addLathe(m, s.base, poly, segments);
      break;
    }
  }
  return m;
}

}  // namespace mf::render
