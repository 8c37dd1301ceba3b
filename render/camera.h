// A pinhole camera: position, look-at point and vertical field of view, up = +y; and the pose of
// a moving camera ([[render.camera_key]]) at a time.
#pragma once

#include <algorithm>
#include <cmath>

#include "settings.h"
#include "warp.h"

namespace mf::render {

struct Camera {
  Vec3 position, u, v, w;  // right, up, forward
  int width = 0, height = 0;
  Real tanHalf = 0, aspect = 1;

  explicit Camera(const RenderSettings& s)
      : position(s.cameraPosition), width(s.width), height(s.height),
        tanHalf(std::tan(0.5 * s.fov * M_PI / 180)), aspect(Real(s.width) / s.height) {
    w = unit(s.lookAt - s.cameraPosition);
    u = unit(cross(w, Vec3{0, 1, 0}));
    if (lengthSquared(u) == 0) u = {1, 0, 0};
    v = cross(u, w);
  }

  /// The image point (pixels from the top-left corner) that p projects to; false behind the
  /// camera. The inverse of direction().
  bool project(const Vec3& p, Real& x, Real& y) const {
    const Vec3 q = p - position;
    const Real z = dot(q, w);
    if (!(z > 0)) return false;
    x = (dot(q, u) / z / (tanHalf * aspect) + 1) * width / 2;
    y = (1 - dot(q, v) / z / tanHalf) * height / 2;
    return true;
  }

  /// The unit direction through image point (x, y), in pixels from the top-left corner.
  Vec3 direction(Real x, Real y) const {
    const Real px = (2 * x / width - 1) * tanHalf * aspect;
    const Real py = (1 - 2 * y / height) * tanHalf;
    return unit(w + u * px + v * py);
  }
};

/// The camera of `keys` at time t: each of position, look-at point and fov a cubic Hermite
/// spline through the keys, its tangents Catmull-Rom's on the keys' times ((p[k+1] - p[k-1]) /
/// (t[k+1] - t[k-1])) and zero at the first and last key, so that the camera eases in and out and
/// its velocity is continuous at every key. Held before the first key and after the last.
inline CameraKey cameraAt(const std::vector<CameraKey>& keys, Real t) {
  if (keys.empty()) return {};
  if (t <= keys.front().time) return keys.front();
  if (t >= keys.back().time) return keys.back();
  size_t k = 0;
  while (keys[k + 1].time <= t) ++k;
  const CameraKey &a = keys[k], &b = keys[k + 1];
  const Real dt = b.time - a.time, s = (t - a.time) / dt;
  const Real h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s), h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
  // Tangents per unit time; the Hermite basis takes them per unit s (times dt).
  auto tangent = [&](size_t i, auto member) {
    using T = std::decay_t<decltype(keys[i].*member)>;
    if (i == 0 || i + 1 == keys.size()) return T{};
    return (keys[i + 1].*member - keys[i - 1].*member) / (keys[i + 1].time - keys[i - 1].time);
  };
  auto blend = [&](auto member) {
    return a.*member * h00 + tangent(k, member) * (h10 * dt) + b.*member * h01 + tangent(k + 1, member) * (h11 * dt);
  };
  CameraKey c;
  c.time = t;
  c.position = blend(&CameraKey::position);
  c.lookAt = blend(&CameraKey::lookAt);
  c.fov = std::clamp(blend(&CameraKey::fov), Real(1), Real(170));
  return c;
}

/// `settings` with its camera at time t (unchanged without camera keys).
inline RenderSettings atTime(RenderSettings settings, Real t) {
  if (settings.cameraKeys.empty()) return settings;
  const CameraKey c = cameraAt(settings.cameraKeys, t);
  settings.cameraPosition = c.position, settings.lookAt = c.lookAt, settings.fov = c.fov;
  return settings;
}

}  // namespace mf::render
