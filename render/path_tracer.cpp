#include "path_tracer.h"
#include "sampler.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

namespace mf::render {

namespace {

using Clock = std::chrono::steady_clock;


// The shading path is small functions on doubles; a call there spills every live register (the
// x86-64 ABI saves none), which cost more than the arithmetic. The hot ones are forced inline.
#define MF_INLINE inline __attribute__((always_inline))

/// mf::normalize with the same operations (the same bits), always inlined.
MF_INLINE Vec3 unit(const Vec3& a) {
  const Real l = std::sqrt(dot(a, a));
  return l > 0 ? a / l : Vec3{};
}

Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
Vec3 expNeg(const Vec3& sigma, Real d) { return {std::exp(-sigma.x * d), std::exp(-sigma.y * d), std::exp(-sigma.z * d)}; }
Real maxComponent(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// An orthonormal frame around n (Duff et al. 2017).
void basis(const Vec3& n, Vec3& t, Vec3& b) {
  const Real s = std::copysign(1.0, n.z), a = -1.0 / (s + n.z), c = n.x * n.y * a;
  t = {1 + s * n.x * n.x * a, s * c, -s * n.x};
  b = {c, s + n.y * n.y * a, -n.y};
}

MF_INLINE Vec3 cosineHemisphere(const Vec3& n, Real u1, Real u2) {
  const Real r = std::sqrt(u1), phi = 2 * M_PI * u2;
  Vec3 t, b;
  basis(n, t, b);
  return unit(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1 - u1)));
}

Vec3 uniformSphere(Real u1, Real u2) {
  const Real z = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Unpolarised Fresnel reflectance for a dielectric interface.
Real fresnel(Real cosi, Real cost, Real n1, Real n2) {
  const Real rs = (n1 * cosi - n2 * cost) / (n1 * cosi + n2 * cost);
  const Real rp = (n1 * cost - n2 * cosi) / (n1 * cost + n2 * cosi);
  return 0.5 * (rs * rs + rp * rp);
}

/// The volumes a ray is inside, as material indices; the one with the highest priority is the
/// medium the ray travels in (ties: the last entered).
struct MediumStack {
  static constexpr int kMax = 16;
  int entries[kMax];
  int size = 0;

  int top(const std::vector<MaterialSpec>& m) const {
    int best = -1;
    for (int i = 0; i < size; ++i)
      if (best < 0 || m[entries[i]].priority >= m[best].priority) best = entries[i];
    return best;
  }
  void push(int material) {
    if (size < kMax) entries[size++] = material;
  }
  void remove(int material) {  // the last entry of that material
    for (int i = size - 1; i >= 0; --i)
      if (entries[i] == material) {
        for (int j = i; j + 1 < size; ++j) entries[j] = entries[j + 1];
        --size;
        return;
      }
  }
  bool contains(int material) const {
    for (int i = 0; i < size; ++i)
      if (entries[i] == material) return true;
    return false;
  }
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

void skipFilter(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] && RTCHitN_geomID(args->hit, args->N, i) == c->skipGeometry &&
        RTCRayN_tfar(args->ray, args->N, i) < c->skipDistance)
      args->valid[i] = 0;
}

/// The power heuristic (Veach 1997, beta = 2): the weight of the strategy with density `a`.
MF_INLINE Real powerHeuristic(Real a, Real b) { return a * a / (a * a + b * b); }

/// The density of a uniform cone of directions with cosine `cosMax`, and a sample of it.
MF_INLINE Real conePdf(Real cosMax) { return 1 / (2 * M_PI * (1 - cosMax)); }
Vec3 sampleCone(const Vec3& axis, Real cosMax, Real u1, Real u2) {
  const Real cosT = 1 - u1 * (1 - cosMax), sinT = std::sqrt(std::max(0.0, 1 - cosT * cosT)), phi = 2 * M_PI * u2;
  Vec3 t, b;
  basis(axis, t, b);
  return unit(t * (sinT * std::cos(phi)) + b * (sinT * std::sin(phi)) + axis * cosT);
}

RTCBounds emptyBox() { return {1e30f, 1e30f, 1e30f, 0, -1e30f, -1e30f, -1e30f, 0}; }
void grow(RTCBounds& a, const RTCBounds& b) {
  a.lower_x = std::min(a.lower_x, b.lower_x), a.lower_y = std::min(a.lower_y, b.lower_y), a.lower_z = std::min(a.lower_z, b.lower_z);
  a.upper_x = std::max(a.upper_x, b.upper_x), a.upper_y = std::max(a.upper_y, b.upper_y), a.upper_z = std::max(a.upper_z, b.upper_z);
}
bool overlap(const RTCBounds& a, const RTCBounds& b) {
  return a.lower_x <= b.upper_x && b.lower_x <= a.upper_x && a.lower_y <= b.upper_y && b.lower_y <= a.upper_y &&
         a.lower_z <= b.upper_z && b.lower_z <= a.upper_z;
}

struct Hit {
  enum Kind { None, Mesh, Floor, Light } kind = None;
  Real t = 0;
  int material = -1;  // also the geometry id
  unsigned prim = 0;  // the triangle (meshes)
  Vec3 p, ng, ns;  // point, geometric normal (outward of the material), shading normal
};

}  // namespace

struct PathTracer::Impl {
  RenderSettings settings;
  std::vector<Surface> surfaces;
  std::vector<MaterialSpec> materials;  // one per surface (geometry id)
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Real epsilon = 1e-5;  // ray offset, m: relative to the scene's size
  // Per geometry and triangle: the vertex normals, packed (one load near the hit, not four).
  std::vector<std::vector<std::array<Float3, 3>>> triNormals;
  // Per geometry and triangle: another geometry comes within 2 epsilon of it. A ray leaving a
  // triangle without such a neighbour skips its own surface by tnear = epsilon (nothing else lies
  // that close, so the same hits survive as with the filter); only the others need the filter.
  std::vector<std::vector<uint8_t>> nearOther;
  Vec3 camU, camV, camW;  // right, up, forward
  std::vector<std::string> maskNames;  // the fluids' names (AOV masks)
  std::vector<int> maskOf;             // per geometry: its index in maskNames, -1 for solids

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void build() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    Vec3 lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
    for (size_t g = 0; g < surfaces.size(); ++g) {
      const RenderMesh& m = surfaces[g].mesh;
      RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), std::max<size_t>(m.positions.size(), 1)));
      auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), m.triangles.size()));
      for (size_t i = 0; i < m.positions.size(); ++i) {
        v[3 * i] = m.positions[i].x, v[3 * i + 1] = m.positions[i].y, v[3 * i + 2] = m.positions[i].z;
        lo = cwiseMin(lo, {m.positions[i].x, m.positions[i].y, m.positions[i].z});
        hi = cwiseMax(hi, {m.positions[i].x, m.positions[i].y, m.positions[i].z});
      }
      for (size_t i = 0; i < m.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) idx[3 * i + k] = m.triangles[i][k];
      rtcCommitGeometry(geom);
      rtcAttachGeometryByID(scene, geom, unsigned(g));
      rtcReleaseGeometry(geom);
      materials.push_back(surfaces[g].material);
    }
    if (hi.x > lo.x) epsilon = std::max(1e-6, 2e-5 * length(hi - lo));
    findNeighbours(2 * epsilon);
    bool anyNear = false;
    for (const auto& n : nearOther) anyNear |= std::find(n.begin(), n.end(), 1) != n.end();
    // Robust traversal: refracted rays must not leak through shared edges of a mesh. The skip
    // filter only where another surface lies close to one.
    rtcSetSceneFlags(scene, anyNear ? RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_ROBUST);
    rtcCommitScene(scene);
    triNormals.resize(surfaces.size());
    for (size_t g = 0; g < surfaces.size(); ++g) {
      const RenderMesh& m = surfaces[g].mesh;
      triNormals[g].resize(m.triangles.size());
      for (size_t i = 0; i < m.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) triNormals[g][i][k] = m.normals[m.triangles[i][k]];
    }
    for (const Surface& sf : surfaces) {
      int m = -1;
      if (!sf.solid) {
        m = int(std::find(maskNames.begin(), maskNames.end(), sf.name) - maskNames.begin());
        if (m == int(maskNames.size())) maskNames.push_back(sf.name);
      }
      maskOf.push_back(m);
    }
    camW = unit(settings.lookAt - settings.cameraPosition);
    camU = unit(cross(camW, Vec3{0, 1, 0}));
    if (lengthSquared(camU) == 0) camU = {1, 0, 0};
    camV = cross(camU, camW);
  }

  /// Marks the triangles that come within `margin` of another geometry: Embree's collision
  /// detection (BVH against BVH) of the triangles' bounding boxes, each grown by half the margin.
  void findNeighbours(Real margin) {
    const size_t n = surfaces.size();
    nearOther.assign(n, {});
    for (size_t g = 0; g < n; ++g) nearOther[g].assign(surfaces[g].mesh.triangles.size(), 0);
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
      RTCScene s = rtcNewScene(device);
      RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
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
    } pairs{boxes, nearOther, {}};
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

  Vec3 sky(const Vec3& d) const {
    if (d.y < 0) return settings.skyGround;
    const Real t = std::sqrt(d.y);
    return settings.skyHorizon * (1 - t) + settings.skyZenith * t;
  }

  Vec3 floorAlbedo(const Vec3& p) const {
    if (settings.checkerSize <= 0) return {0.6, 0.6, 0.6};
    const long i = long(std::floor(p.x / settings.checkerSize)) + long(std::floor(p.z / settings.checkerSize));
    return (i & 1) ? Vec3{0.15, 0.15, 0.15} : Vec3{0.75, 0.75, 0.75};
  }

  /// The solid-angle density of directLight's samples from p (0 inside the light).
  Real lightPdf(const Vec3& p) const {
    const Real d2 = lengthSquared(settings.lightPosition - p), r2 = settings.lightRadius * settings.lightRadius;
    if (settings.lightRadius <= 0 || d2 <= r2) return 0;
    return 1 / (2 * M_PI * (1 - std::sqrt(1 - r2 / d2)));
  }

  Real intersectLight(const Vec3& o, const Vec3& d) const {
    if (settings.lightRadius <= 0) return -1;
    const Vec3 oc = o - settings.lightPosition;
    const Real b = dot(oc, d), c = dot(oc, oc) - settings.lightRadius * settings.lightRadius, disc = b * b - c;
    if (disc < 0) return -1;
    const Real s = std::sqrt(disc);
    const Real t0 = -b - s, t1 = -b + s;
    return t0 > epsilon ? t0 : (t1 > epsilon ? t1 : -1);
  }

  /// The nearest hit along o + t d, t in (0, tfar); `leaving`: the geometry o lies on, or -1.
  /// `shading`: also the interpolated shading normal (shadow rays need only the geometric one).
  /// `hit`: the caller's (filled in, not cleared: only what the kind of hit needs is valid).
  /// `knownLight`: intersectLight(o, d) where the caller has it already.
  MF_INLINE void intersect(const Vec3& o, const Vec3& d, Real tfar, int leaving, unsigned leavingPrim, uint64_t& rays,
                 std::vector<RecordedRay>* record, Hit& hit, bool shading = true, const Real* knownLight = nullptr) const {
    hit.kind = Hit::None;
    hit.material = -1;
    SkipContext skip;
    rtcInitIntersectContext(&skip.context);
    float tnear = 0;
    if (leaving >= 0) {
      if (nearOther[leaving][leavingPrim]) {
        skip.context.filter = skipFilter;
        skip.skipGeometry = unsigned(leaving);
        skip.skipDistance = float(epsilon);
      } else {
        tnear = float(epsilon);
      }
    }
    RTCRayHit rh;
    rh.ray.org_x = float(o.x), rh.ray.org_y = float(o.y), rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
    rh.ray.tnear = tnear;
    rh.ray.tfar = float(std::min(tfar, 1e30));
    rh.ray.mask = 0xFFFFFFFF;
    rh.ray.flags = 0;
    rh.ray.time = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    if (record) record->push_back({{rh.ray.org_x, rh.ray.org_y, rh.ray.org_z}, {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z}, tnear, rh.ray.tfar});
    rtcIntersect1(scene, &skip.context, &rh);
    ++rays;
    Real best = tfar;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      best = rh.ray.tfar;
      hit.kind = Hit::Mesh;
      hit.t = best;
      hit.material = int(rh.hit.geomID);
      hit.prim = rh.hit.primID;
      // Embree's Ng is cross(v1 - v0, v2 - v0): outward for our counter-clockwise meshes.
      // Shadow rays use only its side (the sign of dot(d, ng)): unnormalised there.
      hit.ng = Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
      if (shading) {
        hit.ng = unit(hit.ng);
        const auto& tn = triNormals[rh.hit.geomID][rh.hit.primID];
        const Real u = rh.hit.u, v = rh.hit.v;
        const auto& na = tn[0], &nb = tn[1], &nc = tn[2];
        hit.ns = unit(Vec3{na.x, na.y, na.z} * (1 - u - v) + Vec3{nb.x, nb.y, nb.z} * u + Vec3{nc.x, nc.y, nc.z} * v);
        if (dot(hit.ns, hit.ng) <= 0) hit.ns = hit.ng;
      }
    }
    if (settings.floor && d.y < 0 && o.y > settings.floorHeight) {
      const Real t = (settings.floorHeight - o.y) / d.y;
      if (t > epsilon && t < best) {
        best = t;
        hit.kind = Hit::Floor;
        hit.t = t;
        hit.ng = hit.ns = {0, 1, 0};
      }
    }
    const Real tl = knownLight ? *knownLight : intersectLight(o, d);
    if (tl > 0 && tl < best) {
      hit.kind = Hit::Light;
      hit.t = tl;
    }
    if (hit.kind != Hit::None) hit.p = o + d * hit.t;
  }

  /// Transmittance towards a light sample through clear volumes (a transparent-shadow
  /// approximation: refraction does not bend shadow rays). Opaque surfaces and the scattering
  /// of media block light by their extinction.
  /// `crossed`: set when the ray crossed a surface (a path the BSDF sampling cannot make).
  Vec3 transmittance(Vec3 o, const Vec3& d, Real dist, int leaving, unsigned leavingPrim, MediumStack stack, uint64_t& rays,
                     std::vector<RecordedRay>* record, Hit& h, bool& crossed) const {
    crossed = false;
    Vec3 T{1, 1, 1};
    const Real firstLight = dist;  // the caller's intersectLight(o, d)
    for (int crossing = 0; crossing < 32; ++crossing) {
      intersect(o, d, dist, leaving, leavingPrim, rays, record, h, false, crossing == 0 ? &firstLight : nullptr);
      const Real seg = h.kind == Hit::None || h.kind == Hit::Light ? dist : h.t;
      const int medium = stack.top(materials);
      if (medium >= 0) {
        const MaterialSpec& m = materials[medium];
        T = mul(T, expNeg(m.absorption + Vec3{m.scattering, m.scattering, m.scattering}, seg));
      }
      if (h.kind == Hit::None || h.kind == Hit::Light) return T;
      if (h.kind == Hit::Floor) return {};
      const MaterialSpec& m = materials[h.material];
      if (m.kind == MaterialSpec::Kind::Diffuse || m.kind == MaterialSpec::Kind::Emitter) return {};
      if (dot(d, h.ng) < 0) stack.push(h.material);
      else stack.remove(h.material);
      crossed = true;
      if (maxComponent(T) < 1e-4) return {};
      o = h.p;
      leaving = h.material;
      leavingPrim = h.prim;
      dist -= h.t;
      if (dist <= 0) return T;
    }
    return T;
  }

  /// Light from the spherical lamp at p with a cosine (surface) or isotropic (medium) lobe,
  /// sampled uniformly in the cone the sphere subtends (u1, u2), weighted by the power heuristic
  /// against the lobe's own sampling where that can find the same path (see trace).
  /// `cone`: instead, a uniform cone of directions around *cone with cosine coneCos (a
  /// regularised mirror, see trace).
  Vec3 directLight(const Vec3& p, const Vec3* normal, int leaving, unsigned leavingPrim, const MediumStack& stack, Real u1, Real u2,
                   uint64_t& rays, std::vector<RecordedRay>* record, Hit& scratch, const Vec3* cone = nullptr,
                   Real coneCos = 1) const {
    if (settings.lightRadius <= 0) return {};
    const Vec3 toCentre = settings.lightPosition - p;
    const Real d2 = lengthSquared(toCentre), r2 = settings.lightRadius * settings.lightRadius;
    if (d2 <= r2) return {};
    // Uniform sampling of the cone the sphere subtends.
    const Real cosMax = std::sqrt(1 - r2 / d2);
    const Real cosT = 1 - u1 * (1 - cosMax), sinT = std::sqrt(std::max(0.0, 1 - cosT * cosT)), phi = 2 * M_PI * u2;
    const Vec3 w = toCentre / std::sqrt(d2);
    Vec3 t, b;
    basis(w, t, b);
    const Vec3 dir = unit(t * (sinT * std::cos(phi)) + b * (sinT * std::sin(phi)) + w * cosT);
    const Real pdf = 1 / (2 * M_PI * (1 - cosMax));
    Real lobe;  // BSDF or phase function times cosine
    if (cone) {
      if (dot(*cone, dir) < coneCos) return {};
      lobe = conePdf(coneCos);
    } else if (normal) {
      const Real c = dot(*normal, dir);
      if (c <= 0) return {};
      lobe = c / M_PI;
    } else {
      lobe = 1 / (4 * M_PI);
    }
    const Real tl = intersectLight(p, dir);
    if (tl <= 0) return {};
    bool crossed;
    const Vec3 T = transmittance(p, dir, tl, leaving, leavingPrim, stack, rays, record, scratch, crossed);
    // A shadow ray through surfaces stands for paths that refraction would bend: the lobe's
    // sampling never makes them (trace drops its light hits there), so the light sample keeps
    // its full weight.
    const Real weight = crossed || !settings.mis ? 1 : powerHeuristic(pdf, lobe);
    return mul(T, settings.lightEmission) * (weight * lobe / pdf);
  }

  /// The AOVs' view of a hit on the specular chain: the first one's distance and normal (facing
  /// the camera), and the first fluid surface met.
  void recordHit(const Hit& h, const Vec3& d, bool& primary, PrimarySample& first) const {
    if (primary) {
      primary = false;
      if (h.kind != Hit::None) {
        first.depth = h.t;
        Vec3 n = h.kind == Hit::Light ? unit(h.p - settings.lightPosition) : h.ns;
        first.normal = dot(n, d) > 0 ? -n : n;
      }
    }
    if (h.kind == Hit::Mesh && first.mask < 0) first.mask = maskOf[h.material];
  }

  /// `h`, `shadow`: scratch hits (the caller's, so that they are not cleared for every path).
  /// `first`: where to record the primary hit and the specular chain's albedo and fluid (AOVs);
  /// recording draws no samples, so the path is the same with or without.
  Vec3 trace(Vec3 o, Vec3 d, Sampler& smp, uint64_t& rays, std::vector<RecordedRay>* record, Hit& h, Hit& shadow,
             PrimarySample* first = nullptr) const {
    Vec3 L, throughput{1, 1, 1};
    bool primary = first != nullptr;  // the next hit is the camera ray's
    bool chain = first != nullptr;    // no diffuse or scattering vertex yet (the albedo is open)
    auto closeChain = [&](const Vec3& albedo) {
      if (chain) first->albedo = albedo, chain = false;
    };
    MediumStack stack;
    bool lightCounted = false;  // a direct-light estimate already covered this path's next light hit
    bool indirect = false;      // past a diffuse or scattering vertex
    // Multiple importance sampling: the last diffuse or scattering vertex and the density its
    // lobe sampled the direction with, while no surface lies between it and the ray's next hit.
    bool misOpen = false;
    Vec3 misVertex;
    Real misLobePdf = 0;
    int bounces = 0, passes = 0;
    // Light found by following specular chains after a diffuse vertex (caustics: no light
    // sample can find it) has huge variance at a few samples; like Cycles' "clamp indirect", cap
    // such contributions. Light samples (bounded by the light's solid angle) are never capped.
    auto add = [&](const Vec3& c, bool clampable = true) __attribute__((always_inline)) {
      const Real m = maxComponent(c);
      L += clampable && indirect && m > settings.indirectClamp && settings.indirectClamp > 0 ? c * (settings.indirectClamp / m) : c;
    };
    Vec3 start = o;    // where the current segment begins
    Real flight = -1;  // the sampled free flight from `start` in a scattering medium (-1: not drawn)
    Real done = 0;     // how far from `start` absorption and emission are accounted for
    int leaving = -1;  // the geometry the ray starts on
    unsigned leavingPrim = 0;  // and its triangle
    auto newSegment = [&](const Vec3& p) __attribute__((always_inline)) {
      o = start = p;
      flight = -1, done = 0;
    };
    while (bounces < settings.maxDepth) {
      smp.startBounce(bounces);
      intersect(o, d, 1e30, leaving, leavingPrim, rays, record, h);
      if (chain) recordHit(h, d, primary, *first);
      const int medium = stack.top(materials);
      if (medium >= 0) {
        const MaterialSpec& m = materials[medium];
        const Real seg = h.kind == Hit::None ? 1e30 : length(h.p - start);
        if (m.kind == MaterialSpec::Kind::Medium && m.scattering > 0) {
          // Free flight by the scattering coefficient, measured from the segment's start (it goes
          // on through boundaries that do not exist here); absorption weights the segment.
          if (flight < 0) flight = -std::log(1 - smp.next1D()) / m.scattering;
          if (flight < seg) {
            throughput = mul(throughput, expNeg(m.absorption, flight - done));
            add(mul(throughput, m.emission) * (flight - done));
            const Vec3 p = start + d * flight;
            // The medium's single-scattering albedo: the colour each scattering keeps.
            if (chain) {
              const Real ss = m.scattering;
              closeChain({ss / (ss + m.absorption.x), ss / (ss + m.absorption.y), ss / (ss + m.absorption.z)});
            }
            Real u1, u2;
            smp.next2D(u1, u2);
            add(mul(throughput, directLight(p, nullptr, -1, 0, stack, u1, u2, rays, record, shadow)));
            indirect = true;
            lightCounted = true;
            newSegment(p);
            leaving = -1;
            smp.next2D(u1, u2);
            d = uniformSphere(u1, u2);
            misOpen = true, misVertex = p, misLobePdf = 1 / (4 * M_PI);
            ++bounces;
            if (!russianRoulette(throughput, smp)) break;
            continue;
          }
        }
        if (seg < 1e30) {
          if (m.emission != Vec3{}) add(mul(throughput, m.emission) * (seg - done));  // adding zero changes nothing
          throughput = mul(throughput, expNeg(m.absorption, seg - done));
          done = seg;
        }
      }
      if (h.kind == Hit::None) {
        closeChain({1, 1, 1});
        add(mul(throughput, sky(d)));
        break;
      }
      if (h.kind == Hit::Light) {
        closeChain({1, 1, 1});
        if (misOpen) {  // the light sample at misVertex could have found this path too
          const Real w = settings.mis ? powerHeuristic(misLobePdf, lightPdf(misVertex)) : 0;
          if (w > 0) add(mul(throughput, settings.lightEmission) * w, false);
        } else if (!lightCounted) {
          add(mul(throughput, settings.lightEmission));
        }
        break;
      }
      misOpen = false;  // any surface ends what the light sample could have seen
      const MaterialSpec* m = h.kind == Hit::Mesh ? &materials[h.material] : nullptr;
      if (m && m->kind == MaterialSpec::Kind::Emitter) {
        closeChain({1, 1, 1});
        add(mul(throughput, m->emission));
        break;
      }
      if (!m || m->kind == MaterialSpec::Kind::Diffuse) {  // the table, or a diffuse mesh
        const Vec3 albedo = m ? m->colour : floorAlbedo(h.p);
        closeChain(albedo);
        if (dot(d, h.ng) > 0) h.ng = -h.ng, h.ns = -h.ns;  // face the incoming ray
        add(mul(throughput, diffuseBounce(h, albedo, o, d, stack, smp, rays, record, shadow)), false);
        leaving = m ? h.material : -1;
        leavingPrim = h.prim;
        indirect = true;
        throughput = mul(throughput, albedo);
        start = o, flight = -1, done = 0;
        misOpen = true, misVertex = o, misLobePdf = std::max(0.0, dot(d, h.ns)) / M_PI;
        lightCounted = true;
        ++bounces;
        if (!russianRoulette(throughput, smp)) break;
        continue;
      }
      // A dielectric boundary (clear liquid, glass, bubble, or a medium's surface).
      const bool entering = dot(d, h.ng) < 0;
      const int current = medium;  // the stack has not changed since
      // Leaving a volume is real when it is the medium, or when the ray was never known to be in it.
      const bool real = entering ? m->priority >= (current < 0 ? -1 : materials[current].priority)
                                 : current == h.material || !stack.contains(h.material);
      if (!real) {
        // Inside a volume of higher priority: this boundary does not exist there.
        if (entering) stack.push(h.material);
        else stack.remove(h.material);
        o = h.p;
        leaving = h.material;
        leavingPrim = h.prim;
        if (++passes > 64) break;
        continue;  // the segment goes on from `start`
      }
      MediumStack after = stack;
      if (entering) after.push(h.material);
      else after.remove(h.material);
      const int outsideMedium = entering ? current : after.top(materials);
      const Real n1 = entering ? (current >= 0 ? materials[current].ior : 1.0) : m->ior;
      const Real n2 = entering ? m->ior : (outsideMedium >= 0 ? materials[outsideMedium].ior : 1.0);
      const Vec3 incidentSide = entering ? h.ng : -h.ng;  // geometric normal on the ray's side
      Vec3 n = entering ? h.ns : -h.ns;
      Real cosi = -dot(d, n);
      if (cosi <= 0) n = incidentSide, cosi = -dot(d, n);
      const Real eta = n1 / n2, sin2t = eta * eta * std::max(0.0, 1 - cosi * cosi);
      Real F = 1, cost = 0;
      if (sin2t < 1) {
        cost = std::sqrt(1 - sin2t);
        F = fresnel(cosi, cost, n1, n2);
      }
      Vec3 next;
      bool reflect = smp.next1D() < F;
      if (!reflect) {
        next = unit(d * eta + n * (eta * cosi - cost));
        if (dot(next, incidentSide) >= 0) reflect = true;  // shading normal bent it back
      }
      if (reflect) {
        next = unit(d + n * (2 * cosi));
        if (dot(next, incidentSide) <= 0) next = unit(d + incidentSide * (-2 * dot(d, incidentSide)));
        lightCounted = false;  // reflections are not covered by the transparent shadow rays
        if (indirect && settings.regularise > 0) {
          // Path regularisation (Kaplanyan & Dachsbacher 2013): after a diffuse or scattering
          // vertex the mirror becomes a uniform cone of half-angle `regularise`, so that a light
          // sample finds the lamp through it (MIS with the cone's own sampling): a caustic by
          // reflection is blurred by that angle instead of being a rare, clamped firefly.
          const Real coneCos = std::cos(settings.regularise * M_PI / 180);
          Real u1, u2;
          smp.next2D(u1, u2);
          add(mul(throughput, directLight(h.p, nullptr, h.material, h.prim, stack, u1, u2, rays, record, shadow, &next, coneCos)),
              false);
          smp.next2D(u1, u2);
          const Vec3 blurred = sampleCone(next, coneCos, u1, u2);
          if (dot(blurred, incidentSide) <= 0) break;  // into the surface: lost
          next = blurred;
          misOpen = true, misVertex = h.p, misLobePdf = conePdf(coneCos);
          lightCounted = true;
        }
      } else {
        stack = after;
      }
      newSegment(h.p);
      leaving = h.material;
      leavingPrim = h.prim;
      d = next;
      ++bounces;
      if (!russianRoulette(throughput, smp)) break;
    }
    return L;
  }

  Vec3 diffuseBounce(const Hit& h, const Vec3& albedo, Vec3& o, Vec3& d, const MediumStack& stack, Sampler& smp,
                     uint64_t& rays, std::vector<RecordedRay>* record, Hit& scratch) const {
    // Meshes: start on the surface and skip it (see SkipContext); the analytic floor: offset.
    const bool mesh = h.kind == Hit::Mesh;
    const Vec3 p = mesh ? h.p : h.p + h.ng * epsilon;
    Real u1, u2;
    smp.next2D(u1, u2);
    const Vec3 direct = mul(albedo, directLight(p, &h.ns, mesh ? h.material : -1, h.prim, stack, u1, u2, rays, record, scratch));
    o = p;
    smp.next2D(u1, u2);
    d = cosineHemisphere(h.ns, u1, u2);
    if (dot(d, h.ng) <= 0) {
      smp.next2D(u1, u2);
      d = cosineHemisphere(h.ng, u1, u2);
    }
    return direct;
  }

  /// Russian roulette from the fourth bounce on, as pbrt-v4 plays it: a path survives with
  /// probability q = its throughput's largest component where that is below 1 (never killed
  /// otherwise: chains through clear glass keep a throughput near 1), and the survivors are
  /// weighted by 1 / q: unbiased. `smp` is at the bounce that just ended.
  MF_INLINE static bool russianRoulette(Vec3& throughput, Sampler& smp) {
    if (smp.bounce() < 3) return true;
    const Real q = maxComponent(throughput);
    if (q >= 1) return true;
    if (q <= 0 || smp.next1D() >= q) return false;
    throughput *= 1 / q;
    return true;
  }
};

PathTracer::PathTracer(std::vector<Surface> surfaces, const RenderSettings& settings) : impl_(std::make_unique<Impl>()) {
  impl_->settings = settings;
  impl_->surfaces = std::move(surfaces);
  impl_->build();
}

PathTracer::~PathTracer() = default;

size_t PathTracer::triangleCount() const {
  size_t n = 0;
  for (const auto& s : impl_->surfaces) n += s.mesh.size();
  return n;
}

std::vector<std::string> PathTracer::maskNames() const { return impl_->maskNames; }

Image PathTracer::render(int frame, RenderStats* stats, const std::function<void(int, int)>& progress,
                         std::vector<RecordedRay>* record, Aovs* aovs) const {
  const Impl& im = *impl_;
  const RenderSettings& s = im.settings;
  Image image(s.width, s.height);
  if (aovs) *aovs = Aovs(s.width, s.height, im.maskNames);
  const auto t0 = Clock::now();
  tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
  tbb::combinable<std::vector<RecordedRay>> recorded;
  std::atomic<int> rowsDone{0};
  std::mutex progressMutex;
  const Real tanHalf = std::tan(0.5 * s.fov * M_PI / 180), aspect = Real(s.width) / s.height;
  // One row per task: pixels are independent, so the schedule cannot change any value.
  tbb::parallel_for(tbb::blocked_range<int>(0, s.height, 1), [&](const tbb::blocked_range<int>& rows) {
    uint64_t& count = rays.local();
    std::vector<RecordedRay>* rec = record ? &recorded.local() : nullptr;
    Hit hit, shadow;
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < s.width; ++x) {
        Vec3 sum;
        AovPixel aov(aovs ? im.maskNames.size() : 0);
        // The frame is part of the pixel's seed only with animated_seed (see docs/rendering.md).
        const uint64_t seed = Sampler::pixelSeed(x, y, s.animatedSeed ? uint64_t(frame) + 1 : 0);
        for (int k = 0; k < s.samples; ++k) {
          Sampler smp(seed, uint32_t(k), !s.sobol);
          Real jx, jy;
          smp.get2D(0, jx, jy);
          const Real px = (2 * (x + jx) / s.width - 1) * tanHalf * aspect;
          const Real py = (1 - 2 * (y + jy) / s.height) * tanHalf;
          const Vec3 d = unit(im.camW + im.camU * px + im.camV * py);
          PrimarySample first;
          Vec3 c = im.trace(s.cameraPosition, d, smp, count, rec, hit, shadow, aovs ? &first : nullptr);
          if (!isFinite(c)) c = {};
          sum += c;
          if (aovs) aov.add(first, c);
        }
        image.set(x, y, sum / Real(s.samples));
        if (aovs) aov.store(*aovs, x, y);
      }
      const int done = ++rowsDone;
      if (progress) {
        std::lock_guard<std::mutex> lock(progressMutex);
        progress(done, s.height);
      }
    }
  });
  if (stats) {
    stats->rays = rays.combine(std::plus<uint64_t>());
    stats->seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  if (record) recorded.combine_each([&](const std::vector<RecordedRay>& r) { record->insert(record->end(), r.begin(), r.end()); });
  return image;
}

double PathTracer::coverage(const std::function<bool(const Surface&)>& counts) const {
  const Impl& im = *impl_;
  const RenderSettings& s = im.settings;
  const Real tanHalf = std::tan(0.5 * s.fov * M_PI / 180), aspect = Real(s.width) / s.height;
  std::vector<uint8_t> accept(im.surfaces.size());
  for (size_t g = 0; g < im.surfaces.size(); ++g) accept[g] = counts(im.surfaces[g]);
  const uint64_t covered = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, s.height), uint64_t(0),
      [&](const tbb::blocked_range<int>& rows, uint64_t n) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = 0; x < s.width; ++x) {
            const Vec3 d = unit(im.camW + im.camU * ((2 * (x + 0.5) / s.width - 1) * tanHalf * aspect) +
                                im.camV * ((1 - 2 * (y + 0.5) / s.height) * tanHalf));
            float tnear = 0;
            for (int bounce = 0; bounce < 64; ++bounce) {
              RTCRayHit rh;
              rh.ray.org_x = float(s.cameraPosition.x), rh.ray.org_y = float(s.cameraPosition.y), rh.ray.org_z = float(s.cameraPosition.z);
              rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
              rh.ray.tnear = tnear;
              rh.ray.tfar = std::numeric_limits<float>::infinity();
              rh.ray.mask = 0xFFFFFFFF;
              rh.ray.flags = 0;
              rh.ray.time = 0;
              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
              rtcIntersect1(im.scene, &context, &rh);
              if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
              if (accept[rh.hit.geomID]) {
                ++n;
                break;
              }
              tnear = rh.ray.tfar * (1 + 1e-6f) + float(im.epsilon);
            }
          }
        return n;
      },
      std::plus<uint64_t>());
  return s.width > 0 && s.height > 0 ? double(covered) / (double(s.width) * s.height) : 0;
}

double PathTracer::traceBare(const std::vector<RecordedRay>& rays) const {
  const auto t0 = Clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = r.begin(); i < r.end(); ++i) {
      RTCRayHit rh;
      rh.ray.org_x = rays[i].org[0], rh.ray.org_y = rays[i].org[1], rh.ray.org_z = rays[i].org[2];
      rh.ray.dir_x = rays[i].dir[0], rh.ray.dir_y = rays[i].dir[1], rh.ray.dir_z = rays[i].dir[2];
      rh.ray.tnear = rays[i].tnear;
      rh.ray.tfar = rays[i].tfar;
      rh.ray.mask = 0xFFFFFFFF;
      rh.ray.flags = 0;
      rh.ray.time = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(impl_->scene, &context, &rh);
    }
  });
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::vector<Surface> solidSurfaces(const Scene& scene) {
  std::vector<Surface> out;
  for (size_t i = 0; i < scene.solids.size(); ++i) {
    const MaterialSpec& m = scene.render.solidMaterials.at(i);
    if (!m.visible) continue;
    out.push_back({scene.solids[i].name.empty() ? "solid" : scene.solids[i].name, solidMesh(scene.solids[i], m.thickness), m, true});
  }
  return out;
}

}  // namespace mf::render
