// The integrator's paths (integrator.h): how one camera ray gathers light.
#include "integrator.h"

#include <algorithm>
#include <cmath>

#include "table.h"

namespace mf::render {

Integrator::Integrator(std::vector<Surface> surfaces_, const RenderSettings& s, double frameInterval)
    : settings(s), surfaces(std::move(surfaces_)), geometry(surfaces, s.shutter * frameInterval),
      epsilon(geometry.epsilon()), camera(s), nextCamera(s), blur(s.shutter > 0 && frameInterval > 0),
      light(s), sky(s), pixelSpread(2 * camera.tanHalf / camera.height / std::sqrt(Real(std::max(1, s.samples)))) {
  for (const Surface& sf : surfaces) {
    materials.push_back(sf.material);
    int m = -1;
    if (!sf.solid) {
      m = int(std::find(maskNames.begin(), maskNames.end(), sf.name) - maskNames.begin());
      if (m == int(maskNames.size())) maskNames.push_back(sf.name);
    }
    maskOf.push_back(m);
    ramps.add(sf);
  }
}

/// The nearest hit along o + t d, t in (0, tfar), of the meshes, the table and the lamp;
/// `leaving`: the geometry o lies on, or -1. `shading`: also the interpolated shading normal
/// (shadow rays need only the geometric one). `hit`: the caller's (filled in, not cleared:
/// only what the kind of hit needs is valid). `knownLight`: light.intersect(o, d) where the
/// caller has it already.
MF_INLINE void Integrator::intersect(const Vec3& o, const Vec3& d, Real tfar, int leaving, unsigned leavingPrim, Hit& hit, bool shading,
                         const Real* knownLight) const {
  geometry.intersect(o, d, tfar, leaving, leavingPrim, hit, shading);
  Real best = hit.kind == Hit::Mesh ? hit.t : tfar;
  if (settings.floor && d.y < 0 && o.y > settings.floorHeight) {
    const Real t = (settings.floorHeight - o.y) / d.y;
    if (t > epsilon && t < best) {
      best = t;
      hit.kind = Hit::Floor;
      hit.t = t;
      hit.ng = hit.ns = {0, 1, 0};
    }
  }
  const Real tl = knownLight ? *knownLight : light.intersect(o, d, epsilon);
  if (tl > 0 && tl < best) {
    hit.kind = Hit::Light;
    hit.t = tl;
  }
  if (hit.kind != Hit::None) hit.p = o + d * hit.t;
}

/// Where a ray goes on from (along d) after the boundary `h`: on the surface, skipping it;
/// after a group of coincident faces (`group`, see crossCoincident), from an epsilon beyond
/// them: skipping only the last face, the ray would meet the others again at t = 0, without end.
MF_INLINE void Integrator::goOnPast(const Hit& h, const Vec3& d, bool group, Vec3& o, int& leaving, unsigned& leavingPrim) const {
  if (group) {
    o = h.p + d * epsilon;
    leaving = -1;
  } else {
    o = h.p;
    leaving = h.material;
    leavingPrim = h.prim;
  }
}

/// Coincident faces are one interface: the faces of other volumes within epsilon of the hit
/// `h` (water clipped to a glass wall's inner face, two volumes with the same surface) enter
/// or leave `after` too, so that the ray goes from the medium before all of them to the medium
/// after all of them, whichever Embree reported first. Returns how many faces were added.
MF_INLINE int Integrator::crossCoincident(const Hit& h, const Vec3& d, MediumStack& after) const {
  if (!geometry.nearAnother(h.material, h.prim)) return 0;
  int group[4] = {h.material};
  int members = 1;
  Hit twin;
  twin.time = h.time;
  twin.log = h.log;
  while (members < 4 && geometry.coincident(h.p, d, group, members, twin)) {
    if (dot(d, twin.ng) < 0) after.push(twin.material);
    else after.remove(twin.material);
    group[members++] = twin.material;
  }
  return members - 1;
}

/// Transmittance towards a light sample through clear volumes (a transparent-shadow
/// approximation: refraction does not bend shadow rays). Opaque surfaces and the scattering
/// of media block light by their extinction.
/// `crossed`: set when the ray crossed a surface (a path the BSDF sampling cannot make).
Vec3 Integrator::transmittance(Vec3 o, const Vec3& d, Real dist, int leaving, unsigned leavingPrim, MediumStack stack, Hit& h, bool& crossed) const {
  crossed = false;
  Vec3 T{1, 1, 1};
  const Real firstLight = dist;  // the caller's light.intersect(o, d)
  for (int crossing = 0; crossing < 32; ++crossing) {
    intersect(o, d, dist, leaving, leavingPrim, h, false, crossing == 0 ? &firstLight : nullptr);
    const Real seg = h.kind == Hit::None || h.kind == Hit::Light ? dist : h.t;
    const int medium = stack.top(materials);
    if (medium >= 0) {
      const MaterialSpec& m = materials[medium];
      if (ramps.heterogeneous(medium)) {
        ramps.march(materials[medium], medium, o, d, 0, seg, T, [](const Vec3&) {});
        T = mul(T, expNeg(Vec3{m.scattering, m.scattering, m.scattering}, seg));
      } else {
        T = mul(T, expNeg(m.absorption + Vec3{m.scattering, m.scattering, m.scattering}, seg));
      }
    }
    if (h.kind == Hit::None || h.kind == Hit::Light) return T;
    if (h.kind == Hit::Floor) return {};
    const MaterialSpec& m = materials[h.material];
    if (m.kind == MaterialSpec::Kind::Diffuse || m.kind == MaterialSpec::Kind::Emitter) return {};
    if (dot(d, h.ng) < 0) stack.push(h.material);
    else stack.remove(h.material);
    const bool group = crossCoincident(h, d, stack) > 0;
    crossed = true;
    if (maxComponent(T) < 1e-4) return {};
    const Vec3 from = o;
    goOnPast(h, d, group, o, leaving, leavingPrim);
    dist -= length(o - from);
    if (dist <= 0) return T;
  }
  return T;
}

/// Light from the spherical lamp at p with a cosine (surface) or isotropic (medium) lobe,
/// sampled uniformly in the cone the sphere subtends (u1, u2), weighted by the power heuristic
/// against the lobe's own sampling where that can find the same path (see trace).
/// `cone`: instead, a uniform cone of directions around *cone with cosine coneCos (a
/// regularised mirror, see trace).
Vec3 Integrator::directLight(const Vec3& p, const Vec3* normal, int leaving, unsigned leavingPrim, const MediumStack& stack, Real u1, Real u2,
                 Hit& scratch, const Vec3* cone, Real coneCos) const {
  if (!light.present()) return {};
  Vec3 dir;
  Real pdf;
  if (!light.sample(p, u1, u2, dir, pdf)) return {};
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
  const Real tl = light.intersect(p, dir, epsilon);
  if (tl <= 0) return {};
  bool crossed;
  const Vec3 T = transmittance(p, dir, tl, leaving, leavingPrim, stack, scratch, crossed);
  // A shadow ray through surfaces stands for paths that refraction would bend: the lobe's
  // sampling never makes them (trace drops its light hits there), so the light sample keeps
  // its full weight.
  const Real weight = crossed || !settings.mis ? 1 : powerHeuristic(pdf, lobe);
  return mul(T, light.emission) * (weight * lobe / pdf);
}

/// The primary hit's image motion to the next frame: its point moved by the surface's
/// velocity (interpolated from the vertices; 0 for solids, the table and the lamp) over the
/// frame interval, projected by the next frame's camera, less where this camera sees it.
void Integrator::recordMotion(const Hit& h, PrimarySample& first) const {
  Vec3 p1 = h.p;
  if (h.kind == Hit::Mesh) {
    const RenderMesh& m = surfaces[h.material].mesh;
    if (!m.velocities.empty()) {
      const auto& tri = m.triangles[h.prim];
      const Float3 &a = m.velocities[tri[0]], &b = m.velocities[tri[1]], &c = m.velocities[tri[2]];
      const Real u = h.u, v = h.v;
      const Vec3 vel = Vec3{a.x, a.y, a.z} * (1 - u - v) + Vec3{b.x, b.y, b.z} * u + Vec3{c.x, c.y, c.z} * v;
      p1 = h.p + vel * frameInterval;
    }
  }
  Real x0, y0, x1, y1;
  if (!camera.project(h.p, x0, y0) || !nextCamera.project(p1, x1, y1)) return;
  first.moved = true;
  first.motion[0] = x1 - x0, first.motion[1] = y1 - y0;
}

/// The AOVs' view of a hit on the specular chain: the first one's distance and normal (facing
/// the camera), and the first fluid surface met.
void Integrator::recordHit(const Hit& h, const Vec3& d, bool& primary, PrimarySample& first) const {
  if (primary) {
    primary = false;
    if (h.kind != Hit::None) {
      first.depth = h.t;
      Vec3 n = h.kind == Hit::Light ? unit(h.p - light.centre) : h.ns;
      first.normal = dot(n, d) > 0 ? -n : n;
      if (frameInterval > 0) recordMotion(h, first);
    }
  }
  if (h.kind == Hit::Mesh && first.mask < 0) first.mask = maskOf[h.material];
}

Vec3 Integrator::trace(Vec3 o, Vec3 d, Sampler& smp, Hit& h, Hit& shadow, PrimarySample* first) const {
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
  Real travelled = 0;  // along the specular chain from the camera: the ray cone's length
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
    intersect(o, d, 1e30, leaving, leavingPrim, h);
    if (chain) recordHit(h, d, primary, *first);
    if (h.kind != Hit::None) travelled += h.t;
    const int medium = stack.top(materials);
    if (medium >= 0) {
      const MaterialSpec& m = materials[medium];
      const Real seg = h.kind == Hit::None ? 1e30 : length(h.p - start);
      if (m.kind == MaterialSpec::Kind::Medium && m.scattering > 0) {
        // Free flight by the scattering coefficient, measured from the segment's start (it goes
        // on through boundaries that do not exist here); absorption weights the segment.
        if (flight < 0) flight = -std::log(1 - smp.next1D()) / m.scattering;
        if (flight < seg) {
          const Vec3 p = start + d * flight;
          Vec3 sigmaA = m.absorption;
          if (ramps.heterogeneous(medium)) {
            ramps.march(materials[medium], medium, start, d, done, flight, throughput, add);
            Vec3 emit;
            ramps.at(materials[medium], medium, p, sigmaA, emit);
          } else {
            throughput = mul(throughput, expNeg(m.absorption, flight - done));
            add(mul(throughput, m.emission) * (flight - done));
          }
          // The medium's single-scattering albedo: the colour each scattering keeps.
          if (chain) {
            const Real ss = m.scattering;
            closeChain({ss / (ss + sigmaA.x), ss / (ss + sigmaA.y), ss / (ss + sigmaA.z)});
          }
          Real u1, u2;
          smp.next2D(u1, u2);
          add(mul(throughput, directLight(p, nullptr, -1, 0, stack, u1, u2, shadow)));
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
        if (ramps.heterogeneous(medium)) {
          ramps.march(materials[medium], medium, start, d, done, seg, throughput, add);
        } else {
          if (m.emission != Vec3{}) add(mul(throughput, m.emission) * (seg - done));  // adding zero changes nothing
          throughput = mul(throughput, expNeg(m.absorption, seg - done));
        }
        done = seg;
      }
    }
    if (h.kind == Hit::None) {
      closeChain({1, 1, 1});
      add(mul(throughput, sky.radiance(d)));
      break;
    }
    if (h.kind == Hit::Light) {
      closeChain({1, 1, 1});
      if (misOpen) {  // the light sample at misVertex could have found this path too
        const Real w = settings.mis ? powerHeuristic(misLobePdf, light.pdf(misVertex)) : 0;
        if (w > 0) add(mul(throughput, light.emission) * w, false);
      } else if (!lightCounted) {
        add(mul(throughput, light.emission));
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
      const Vec3 albedo = m ? m->colour : tableAlbedo(h.p, d, indirect ? 0 : pixelSpread * travelled, settings.checkerSize);
      closeChain(albedo);
      if (dot(d, h.ng) > 0) h.ng = -h.ng, h.ns = -h.ns;  // face the incoming ray
      add(mul(throughput, diffuseBounce(h, albedo, o, d, stack, smp, shadow)), false);
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
    MediumStack after = stack;
    if (entering) after.push(h.material);
    else after.remove(h.material);
    const bool group = crossCoincident(h, d, after) > 0;
    const int beyond = after.top(materials);  // the medium past the interface
    // Leaving a volume is real when it is the medium, or when the ray was never known to be in
    // it; a group of coincident faces, when the medium changes across it.
    const bool real = (entering ? m->priority >= (current < 0 ? -1 : materials[current].priority)
                                : current == h.material || !stack.contains(h.material)) ||
                      (group && beyond != current);
    if (!real) {
      // Inside a volume of higher priority: this boundary does not exist there.
      stack = after;
      goOnPast(h, d, group, o, leaving, leavingPrim);
      if (++passes > 64) break;
      continue;  // the segment goes on from `start`
    }
    // From the medium (the volume left, where the ray was never known to be in it).
    const Real n1 = entering || group || current == h.material ? (current >= 0 ? materials[current].ior : 1.0) : m->ior;
    const Real n2 = entering && !group ? m->ior : (beyond >= 0 ? materials[beyond].ior : 1.0);
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
        add(mul(throughput, directLight(h.p, nullptr, h.material, h.prim, stack, u1, u2, shadow, &next, coneCos)),
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
    d = next;
    newSegment(h.p);  // absorption counts from the boundary
    goOnPast(h, d, group, o, leaving, leavingPrim);
    ++bounces;
    if (!russianRoulette(throughput, smp)) break;
  }
  return L;
}

Vec3 Integrator::diffuseBounce(const Hit& h, const Vec3& albedo, Vec3& o, Vec3& d, const MediumStack& stack, Sampler& smp,
                   Hit& scratch) const {
  // Meshes: start on the surface and skip it (see SkipContext); the analytic floor: offset.
  const bool mesh = h.kind == Hit::Mesh;
  const Vec3 p = mesh ? h.p : h.p + h.ng * epsilon;
  Real u1, u2;
  smp.next2D(u1, u2);
  const Vec3 direct = mul(albedo, directLight(p, &h.ns, mesh ? h.material : -1, h.prim, stack, u1, u2, scratch));
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
MF_INLINE bool Integrator::russianRoulette(Vec3& throughput, Sampler& smp) {
  if (smp.bounce() < 3) return true;
  const Real q = maxComponent(throughput);
  if (q >= 1) return true;
  if (q <= 0 || smp.next1D() >= q) return false;
  throughput *= 1 / q;
  return true;
}

}  // namespace mf::render
