#include "ray_scene.h"

#include <mutex>
#include <stdexcept>

namespace mf::render {

namespace {

RTCBounds emptyBox() { return {1e30f, 1e30f, 1e30f, 0, -1e30f, -1e30f, -1e30f, 0}; }
void grow(RTCBounds& a, const RTCBounds& b) {
  a.lower_x = std::min(a.lower_x, b.lower_x), a.lower_y = std::min(a.lower_y, b.lower_y), a.lower_z = std::min(a.lower_z, b.lower_z);
  a.upper_x = std::max(a.upper_x, b.upper_x), a.upper_y = std::max(a.upper_y, b.upper_y), a.upper_z = std::max(a.upper_z, b.upper_z);
}
bool overlap(const RTCBounds& a, const RTCBounds& b) {
  return a.lower_x <= b.upper_x && b.lower_x <= a.upper_x && a.lower_y <= b.upper_y && b.lower_y <= a.upper_y &&
         a.lower_z <= b.upper_z && b.lower_z <= a.upper_z;
}

}  // namespace

void skipFilter(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] && RTCHitN_geomID(args->hit, args->N, i) == c->skipGeometry &&
        RTCRayN_tfar(args->ray, args->N, i) < c->skipDistance)
      args->valid[i] = 0;
}

void skipSetFilter(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const SkipSetContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (!args->valid[i]) continue;
    const unsigned g = RTCHitN_geomID(args->hit, args->N, i);
    for (int k = 0; k < c->count; ++k)
      if (c->geometries[k] == g) args->valid[i] = 0;
  }
}

RayScene::RayScene(const std::vector<Surface>& surfaces, Real shutterSeconds) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  Vec3 lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
  for (size_t g = 0; g < surfaces.size(); ++g) {
    const RenderMesh& m = surfaces[g].mesh;
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // A moving surface has two time steps, at x - v s/2 and x + v s/2; a still one, one at x.
    const bool moving = shutterSeconds > 0 && m.velocities.size() == m.positions.size() && !m.positions.empty();
    const unsigned steps = moving ? 2 : 1;
    if (moving) rtcSetGeometryTimeStepCount(geom, steps);
    for (unsigned step = 0; step < steps; ++step) {
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), std::max<size_t>(m.positions.size(), 1)));
      const Real f = moving ? (step == 0 ? -0.5 : 0.5) * shutterSeconds : 0;
      for (size_t i = 0; i < m.positions.size(); ++i) {
        const Float3& p = m.positions[i];
        const Float3 vel = moving ? m.velocities[i] : Float3{0, 0, 0};
        v[3 * i] = float(p.x + f * vel.x), v[3 * i + 1] = float(p.y + f * vel.y), v[3 * i + 2] = float(p.z + f * vel.z);
        lo = cwiseMin(lo, {v[3 * i], v[3 * i + 1], v[3 * i + 2]});
        hi = cwiseMax(hi, {v[3 * i], v[3 * i + 1], v[3 * i + 2]});
      }
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = m.triangles[i][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, unsigned(g));
    rtcReleaseGeometry(geom);
  }
  if (hi.x > lo.x) epsilon_ = std::max(1e-6, 2e-5 * length(hi - lo));
  findNeighbours(surfaces, 2 * epsilon_);
  bool anyNear = false;
  for (const auto& n : nearOther_) anyNear |= std::find(n.begin(), n.end(), 1) != n.end();
  // Robust traversal: refracted rays must not leak through shared edges of a mesh. The skip
  // filter only where another surface lies close to one.
  rtcSetSceneFlags(scene_, anyNear ? RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_ROBUST);
  rtcCommitScene(scene_);
  triNormals_.resize(surfaces.size());
  for (size_t g = 0; g < surfaces.size(); ++g) {
    const RenderMesh& m = surfaces[g].mesh;
    triNormals_[g].resize(m.triangles.size());
    for (size_t i = 0; i < m.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) triNormals_[g][i][k] = m.normals[m.triangles[i][k]];
  }
}

RayScene::~RayScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

/// Marks the triangles that come within `margin` of another geometry: Embree's collision
/// detection (BVH against BVH) of the triangles' bounding boxes, each grown by half the margin.
void RayScene::findNeighbours(const std::vector<Surface>& surfaces, Real margin) {
  const size_t n = surfaces.size();
  nearOther_.assign(n, {});
  for (size_t g = 0; g < n; ++g) nearOther_[g].assign(surfaces[g].mesh.triangles.size(), 0);
  if (n < 2) return;
  const float h = float(0.5 * margin);
  std::vector<std::vector<RTCBounds>> boxes(n);
  std::vector<RTCBounds> whole(n, emptyBox());
  for (size_t g = 0; g < n; ++g) {
    const RenderMesh& m = surfaces[g].mesh;
    for (const auto& tri : m.triangles) {
      RTCBounds b = emptyBox();
      for (int k = 0; k < 3; ++k) {
        const Float3& p = m.positions[tri[k]];
        grow(b, {p.x - h, p.y - h, p.z - h, 0, p.x + h, p.y + h, p.z + h, 0});
      }
      boxes[g].push_back(b);
      grow(whole[g], b);
    }
  }
  // rtcCollide takes user geometries only: one scene of boxes per geometry, made when needed.
  std::vector<RTCScene> boxScenes(n, nullptr);
  auto boxScene = [&](size_t g) {
    if (boxScenes[g]) return boxScenes[g];
    RTCScene s = rtcNewScene(device_);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(boxes[g].size()));
    rtcSetGeometryUserData(geom, &boxes[g]);
    rtcSetGeometryBoundsFunction(
        geom,
        [](const RTCBoundsFunctionArguments* a) {
          *a->bounds_o = (*static_cast<const std::vector<RTCBounds>*>(a->geometryUserPtr))[a->primID];
        },
        nullptr);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(s, geom, unsigned(g));
    rtcReleaseGeometry(geom);
    rtcCommitScene(s);
    return boxScenes[g] = s;
  };
  struct Pairs {  // the callback's view (it may run on several threads)
    const std::vector<std::vector<RTCBounds>>& boxes;
    std::vector<std::vector<uint8_t>>& near;
    std::mutex mutex;
  } pairs{boxes, nearOther_, {}};
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      if (boxes[a].empty() || boxes[b].empty() || !overlap(whole[a], whole[b])) continue;
      rtcCollide(
          boxScene(a), boxScene(b),
          [](void* user, RTCCollision* c, unsigned count) {
            auto& p = *static_cast<Pairs*>(user);
            std::lock_guard<std::mutex> lock(p.mutex);
            for (unsigned k = 0; k < count; ++k)  // candidates: the boxes' BVH leaves overlap
              if (overlap(p.boxes[c[k].geomID0][c[k].primID0], p.boxes[c[k].geomID1][c[k].primID1]))
                p.near[c[k].geomID0][c[k].primID0] = p.near[c[k].geomID1][c[k].primID1] = 1;
          },
          &pairs);
    }
  for (RTCScene s : boxScenes)
    if (s) rtcReleaseScene(s);
}

}  // namespace mf::render
