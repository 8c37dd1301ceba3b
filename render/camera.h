// A pinhole camera: position, look-at point and vertical field of view, up = +y.
#pragma once

#include <cmath>

#include "sim/scene.h"
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

  /// The unit direction through image point (x, y), in pixels from the top-left corner.
  Vec3 direction(Real x, Real y) const {
    const Real px = (2 * x / width - 1) * tanHalf * aspect;
    const Real py = (1 - 2 * y / height) * tanHalf;
    return unit(w + u * px + v * py);
  }
};

}  // namespace mf::render
