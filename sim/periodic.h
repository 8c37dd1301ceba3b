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

  /// Calls f(shift) for each image of the box [boxLo, boxHi] that lies within `margin` (per
  /// axis) of the opposite face on every periodic axis it is shifted along: per axis a shift of +length
  /// where the box is within margin of the lower face, -length near the upper one (both, for a
  /// box near both), and every combination of those over the axes but no shift at all, in a
  /// fixed order (x fastest).
  template <class F>
  void forEachImage(const Vec3& boxLo, const Vec3& boxHi, const Vec3& margin, F&& f) const {
    Real shift[3][3];
    int count[3];
    for (int a = 0; a < 3; ++a) {
      shift[a][0] = 0;
      count[a] = 1;
      if (!wraps(a)) continue;
      if (boxLo[a] - lo[a] < margin[a]) shift[a][count[a]++] = length[a];
      if (lo[a] + length[a] - boxHi[a] < margin[a]) shift[a][count[a]++] = -length[a];
    }
    for (int iz = 0; iz < count[2]; ++iz)
      for (int iy = 0; iy < count[1]; ++iy)
        for (int ix = 0; ix < count[0]; ++ix)
          if (ix || iy || iz) f(Vec3(shift[0][ix], shift[1][iy], shift[2][iz]));
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
