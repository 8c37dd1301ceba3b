// Periodic boundaries: along a periodic axis the domain box wraps, so a particle leaving through
// one face comes back through the opposite one and sees the particles there as neighbours. Pair
// separations take the minimum image; that is unique while the period exceeds twice the support
// radius (the scene reader requires it), so a neighbour is found through at most one image.
#pragma once

#include <cmath>
#include <cstdint>

#include "vec3.h"

namespace mf {

struct PeriodicDomain {
  uint8_t axes = 0;  // bit a set: axis a wraps
  Vec3 lo;           // the domain's lower corner
  Vec3 length;       // its extent (the period on periodic axes)

  bool any() const { return axes != 0; }
  bool wraps(int a) const { return (axes >> a) & 1; }

  /// x_i - x_j on the nearest image of j. Plain subtraction (same bits) without periodic axes.
  Vec3 separation(const Vec3& xi, const Vec3& xj) const {
    Vec3 d = xi - xj;
    if (axes == 0) return d;
    for (int a = 0; a < 3; ++a)
      if (wraps(a)) {
        if (d[a] > 0.5 * length[a]) d[a] -= length[a];
        else if (d[a] < -0.5 * length[a]) d[a] += length[a];
      }
    return d;
  }

  /// x brought back into [lo, lo + length) on the periodic axes.
  Vec3 wrap(Vec3 x) const {
    for (int a = 0; a < 3; ++a)
      if (wraps(a) && std::isfinite(x[a])) {
        Real f = x[a] - lo[a];
        if (f < 0 || f >= length[a]) {
          f -= length[a] * std::floor(f / length[a]);
          if (f >= length[a]) f = 0;  // -tiny wraps to exactly length after rounding
          x[a] = lo[a] + f;
        }
      }
    return x;
  }
};

}  // namespace mf
