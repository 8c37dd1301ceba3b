// The path tracer's lights: a spherical area lamp, sampled by the cone it subtends, and a sky
// of three colours (zenith, horizon, ground).
#pragma once

#include "settings.h"
#include "warp.h"

namespace mf::render {

struct Sky {
  Vec3 zenith, horizon, ground;
  explicit Sky(const RenderSettings& s) : zenith(s.skyZenith), horizon(s.skyHorizon), ground(s.skyGround) {}

  /// Radiance from direction d (unit): the ground below the horizon, a blend by sqrt(d.y) above.
  Vec3 radiance(const Vec3& d) const {
    if (d.y < 0) return ground;
    const Real t = std::sqrt(d.y);
    return horizon * (1 - t) + zenith * t;
  }
};

struct SphereLight {
  Vec3 centre, emission;
  Real radius = 0;  // 0: no lamp
  explicit SphereLight(const RenderSettings& s) : centre(s.lightPosition), emission(s.lightEmission), radius(s.lightRadius) {}

  bool present() const { return radius > 0; }

  /// The solid-angle density of sample()'s directions from p (0 inside the light).
  Real pdf(const Vec3& p) const {
    const Real d2 = lengthSquared(centre - p), r2 = radius * radius;
    if (radius <= 0 || d2 <= r2) return 0;
    return 1 / (2 * M_PI * (1 - std::sqrt(1 - r2 / d2)));
  }

  /// A direction from p towards the lamp, uniform in the cone it subtends, and its density;
  /// false where p is inside the lamp.
  bool sample(const Vec3& p, Real u1, Real u2, Vec3& dir, Real& density) const {
    const Vec3 toCentre = centre - p;
    const Real d2 = lengthSquared(toCentre), r2 = radius * radius;
    if (d2 <= r2) return false;
    const Real cosMax = std::sqrt(1 - r2 / d2);
    dir = sampleCone(toCentre / std::sqrt(d2), cosMax, u1, u2);
    density = conePdf(cosMax);
    return true;
  }

  /// The distance along o + t d (d unit) to the lamp's surface beyond `epsilon`, or -1.
  Real intersect(const Vec3& o, const Vec3& d, Real epsilon) const {
    if (radius <= 0) return -1;
    const Vec3 oc = o - centre;
    const Real b = dot(oc, d), c = dot(oc, oc) - radius * radius, disc = b * b - c;
    if (disc < 0) return -1;
    const Real s = std::sqrt(disc);
    const Real t0 = -b - s, t1 = -b + s;
    return t0 > epsilon ? t0 : (t1 > epsilon ? t1 : -1);
  }
};

}  // namespace mf::render
