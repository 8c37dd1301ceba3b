// The path tracer's geometry: every surface's triangles in one Embree 3 scene, with packed
// vertex normals for smooth shading and, per triangle, whether another surface lies within
// twice the ray offset (where a ray leaving it needs the skip filter, see SkipContext).
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry.h"
#include "warp.h"

namespace mf::render {

/// One thread's tally while tracing: the rays cast (RenderStats), and every ray where `record`
/// is set (bench/render_bench replays them for bare traversal).
struct RayLog {
  uint64_t rays = 0;
  std::vector<RecordedRay>* record = nullptr;
};

struct Hit {
  enum Kind { None, Mesh, Floor, Light } kind = None;
  Real t = 0;
  int material = -1;  // also the geometry id
  unsigned prim = 0;  // the triangle (meshes)
  float u = 0, v = 0;  // barycentric coordinates on it (meshes)
  float time = 0;      // where in the shutter the ray is cast, [0, 1) (set by the caller; 0 without blur)
  RayLog* log = nullptr;  // where RayScene counts the ray (set by the caller, like time; null: not counted)
  Vec3 p, ng, ns;  // point, geometric normal (outward of the material), shading normal
};

/// Continuing rays start exactly on the surface they left (an offset would step over a
/// coincident surface, such as water against a glass wall); instead, hits on the geometry just
/// left are ignored closer than `skipDistance`. Where no other geometry lies that close to the
/// triangle left, tnear = skipDistance does the same without the filter (see nearOther).
struct SkipContext {
  RTCIntersectContext context;
  unsigned skipGeometry;
  float skipDistance;
};

void skipFilter(const RTCFilterFunctionNArguments* args);

/// For the search of coincident faces: hits on the geometries listed are ignored.
struct SkipSetContext {
  RTCIntersectContext context;
  unsigned geometries[4];
  int count;
};

void skipSetFilter(const RTCFilterFunctionNArguments* args);

/// An Embree ray, no hit yet.
inline RTCRayHit makeRay(float ox, float oy, float oz, float dx, float dy, float dz, float tnear, float tfar) {
  RTCRayHit rh;
  rh.ray.org_x = ox, rh.ray.org_y = oy, rh.ray.org_z = oz;
  rh.ray.dir_x = dx, rh.ray.dir_y = dy, rh.ray.dir_z = dz;
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFF;
  rh.ray.flags = 0;
  rh.ray.time = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

class RayScene {
 public:
  /// Geometry id g is surfaces[g]. The ray offset is relative to the surfaces' bounding box.
  /// `shutterSeconds` > 0: surfaces with velocities move linearly over the shutter, from
  /// x - v s/2 at ray time 0 to x + v s/2 at time 1 (Embree's motion blur, two time steps).
  explicit RayScene(const std::vector<Surface>& surfaces, Real shutterSeconds = 0);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  RTCScene scene() const { return scene_; }

  /// Whether another geometry comes within two epsilons of triangle `prim` of geometry `g`:
  /// only there can a face coincide with it.
  bool nearAnother(int g, unsigned prim) const { return nearOther_[size_t(g)][prim] != 0; }

  /// A face of a geometry not among `skip` (count of them) within an epsilon either side of p,
  /// along the line p + t d: a face coincident with the one at p, which float rounding may put
  /// just behind p. Fills hit.material, prim, ng (unit) and t (from p); false when none.
  MF_INLINE bool coincident(const Vec3& p, const Vec3& d, const int* skip, int count, Hit& hit) const {
    SkipSetContext c;
    rtcInitIntersectContext(&c.context);
    c.context.filter = skipSetFilter;
    c.count = std::min(count, 4);
    for (int k = 0; k < c.count; ++k) c.geometries[k] = unsigned(skip[k]);
    const Vec3 from = p - d * epsilon_;
    RTCRayHit rh = makeRay(float(from.x), float(from.y), float(from.z), float(d.x), float(d.y), float(d.z), 0,
                           float(2 * epsilon_));
    rh.ray.time = hit.time;
    rtcIntersect1(scene_, &c.context, &rh);
    if (hit.log) ++hit.log->rays;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.kind = Hit::Mesh;
    hit.t = rh.ray.tfar - epsilon_;
    hit.material = int(rh.hit.geomID);
    hit.prim = rh.hit.primID;
    hit.ng = unit(Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
    hit.p = p;
    return true;
  }
  Real epsilon() const { return epsilon_; }  // ray offset, m

  /// The nearest triangle along o + t d, t in (0, tfar): hit.kind Mesh (t, material, prim, ng,
  /// and with `shading` the interpolated normal ns) or None; `leaving`: the geometry o lies on,
  /// or -1. Counts the ray in hit.log, and records it where the log keeps rays.
  MF_INLINE void intersect(const Vec3& o, const Vec3& d, Real tfar, int leaving, unsigned leavingPrim, Hit& hit, bool shading) const {
    hit.kind = Hit::None;
    hit.material = -1;
    SkipContext skip;
    rtcInitIntersectContext(&skip.context);
    float tnear = 0;
    if (leaving >= 0) {
      if (nearOther_[leaving][leavingPrim]) {
        skip.context.filter = skipFilter;
        skip.skipGeometry = unsigned(leaving);
        skip.skipDistance = float(epsilon_);
      } else {
        tnear = float(epsilon_);
      }
    }
    RTCRayHit rh = makeRay(float(o.x), float(o.y), float(o.z), float(d.x), float(d.y), float(d.z), tnear,
                           float(std::min(tfar, 1e30)));
    rh.ray.time = hit.time;
    RayLog* log = hit.log;
    if (log && log->record)
      log->record->push_back({{rh.ray.org_x, rh.ray.org_y, rh.ray.org_z}, {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z}, tnear, rh.ray.tfar});
    rtcIntersect1(scene_, &skip.context, &rh);
    if (log) ++log->rays;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
    hit.kind = Hit::Mesh;
    hit.t = rh.ray.tfar;
    hit.material = int(rh.hit.geomID);
    hit.prim = rh.hit.primID;
    hit.u = rh.hit.u, hit.v = rh.hit.v;
    // Embree's Ng is cross(v1 - v0, v2 - v0): outward for our counter-clockwise meshes.
    // Shadow rays use only its side (the sign of dot(d, ng)): unnormalised there.
    hit.ng = Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    if (shading) {
      hit.ng = unit(hit.ng);
      const auto& tn = triNormals_[rh.hit.geomID][rh.hit.primID];
      const Real u = rh.hit.u, v = rh.hit.v;
      const auto& na = tn[0], &nb = tn[1], &nc = tn[2];
      hit.ns = unit(Vec3{na.x, na.y, na.z} * (1 - u - v) + Vec3{nb.x, nb.y, nb.z} * u + Vec3{nc.x, nc.y, nc.z} * v);
      if (dot(hit.ns, hit.ng) <= 0) hit.ns = hit.ng;
    }
  }

 private:
  void findNeighbours(const std::vector<Surface>& surfaces, Real margin);

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  Real epsilon_ = 1e-5;
  // Per geometry and triangle: the vertex normals, packed (one load near the hit, not four).
  std::vector<std::vector<std::array<Float3, 3>>> triNormals_;
  // Per geometry and triangle: another geometry comes within 2 epsilon of it. A ray leaving a
  // triangle without such a neighbour skips its own surface by tnear = epsilon (nothing else lies
  // that close, so the same hits survive as with the filter); only the others need the filter.
  std::vector<std::vector<uint8_t>> nearOther_;
};

}  // namespace mf::render
