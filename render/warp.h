// The path tracer's small vector and sampling functions: directions drawn from uniform numbers
// (hemisphere, sphere, cone) with their densities, and the MIS weight. Header-only and forced
// inline: the shading path is small functions on doubles, and a call there spills every live
// register (the x86-64 ABI saves none), which costs more than the arithmetic.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/vec3.h"

#define MF_INLINE inline __attribute__((always_inline))

namespace mf::render {

/// mf::normalize with the same operations (the same bits), always inlined.
MF_INLINE Vec3 unit(const Vec3& a) {
  const Real l = std::sqrt(dot(a, a));
  return l > 0 ? a / l : Vec3{};
}

inline Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3 expNeg(const Vec3& sigma, Real d) { return {std::exp(-sigma.x * d), std::exp(-sigma.y * d), std::exp(-sigma.z * d)}; }
inline Real maxComponent(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// An orthonormal frame around n (Duff et al. 2017).
inline void basis(const Vec3& n, Vec3& t, Vec3& b) {
  const Real s = std::copysign(1.0, n.z), a = -1.0 / (s + n.z), c = n.x * n.y * a;
  t = {1 + s * n.x * n.x * a, s * c, -s * n.x};
  b = {c, s + n.y * n.y * a, -n.y};
}

/// A cosine-weighted direction around n (density cos / pi).
MF_INLINE Vec3 cosineHemisphere(const Vec3& n, Real u1, Real u2) {
  const Real r = std::sqrt(u1), phi = 2 * M_PI * u2;
  Vec3 t, b;
  basis(n, t, b);
  return unit(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1 - u1)));
}

/// A uniform direction (density 1 / 4 pi).
inline Vec3 uniformSphere(Real u1, Real u2) {
  const Real z = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

/// The density of a uniform cone of directions with cosine `cosMax`, and a sample of it.
MF_INLINE Real conePdf(Real cosMax) { return 1 / (2 * M_PI * (1 - cosMax)); }
inline Vec3 sampleCone(const Vec3& axis, Real cosMax, Real u1, Real u2) {
  const Real cosT = 1 - u1 * (1 - cosMax), sinT = std::sqrt(std::max(0.0, 1 - cosT * cosT)), phi = 2 * M_PI * u2;
  Vec3 t, b;
  basis(axis, t, b);
  return unit(t * (sinT * std::cos(phi)) + b * (sinT * std::sin(phi)) + axis * cosT);
}

/// The power heuristic (Veach 1997, beta = 2): the weight of the strategy with density `a`.
MF_INLINE Real powerHeuristic(Real a, Real b) { return a * a / (a * a + b * b); }

}  // namespace mf::render
