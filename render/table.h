// The table under the scene: a checkerboard texture, box-filtered over a ray's footprint so
// that squares smaller than a pixel give their mean instead of flickering from sample to sample.
#pragma once

#include <algorithm>
#include <cmath>

#include "warp.h"

namespace mf::render {

/// The fraction of [x - h, x + h] where floor(x) is odd (h = 0: 0 or 1), from the integral of
/// that indicator, B(x) = floor(x/2) + max(x - 2 floor(x/2) - 1, 0).
inline Real oddFraction(Real x, Real h) {
  if (h <= 0 || std::floor(x - h) == std::floor(x + h)) return (long(std::floor(x)) & 1) ? 1 : 0;
  auto B = [](Real y) {
    const Real f = std::floor(y / 2);
    return f + std::max(y - 2 * f - 1, Real(0));
  };
  return (B(x + h) - B(x - h)) / (2 * h);
}

/// The table top's colour at p: a checkerboard of `checkerSize`, or plain grey (size 0). Seen
/// along a specular chain from the camera, the checkerboard is box-filtered over the ray's
/// footprint on the table (a ray cone: `width` across the ray, stretched by 1/|d.y| along it);
/// width 0 (after a diffuse bounce) takes a point sample.
inline Vec3 tableAlbedo(const Vec3& p, const Vec3& d, Real width, Real checkerSize) {
  if (checkerSize <= 0) return {0.6, 0.6, 0.6};
  const Real cs = checkerSize;
  Real hx = 0, hz = 0;  // the footprint's half-extents along x and z, in squares
  if (width > 0) {
    const Real across = std::hypot(d.x, d.z);
    const Real ux = across > 0 ? d.x / across : 1, uz = across > 0 ? d.z / across : 0;
    const Real along = width / std::max(std::abs(d.y), Real(1e-3));
    hx = 0.5 * std::hypot(along * ux, width * uz) / cs;
    hz = 0.5 * std::hypot(along * uz, width * ux) / cs;
  }
  // A square is dark where exactly one of floor(x), floor(z) is odd.
  const Real fx = oddFraction(p.x / cs, hx), fz = oddFraction(p.z / cs, hz);
  const Real dark = fx * (1 - fz) + fz * (1 - fx);
  return Vec3{0.75, 0.75, 0.75} * (1 - dark) + Vec3{0.15, 0.15, 0.15} * dark;
}

}  // namespace mf::render
