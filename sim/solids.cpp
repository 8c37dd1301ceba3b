#include "solids.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace mf {

namespace {

int divisions(Real length, Real spacing) { return std::max(1, int(std::lround(length / spacing))); }

void sampleBox(const SolidSpec& s, Real spacing, const PeriodicDomain& periodic, std::vector<Vec3>& out) {
  const Vec3 ext = s.max - s.min;
  const int n[3] = {divisions(ext.x, spacing), divisions(ext.y, spacing), divisions(ext.z, spacing)};
  auto coord = [&](int axis, int i) { return s.min[axis] + ext[axis] * Real(i) / n[axis]; };
  // On a periodic axis index n is index 0's image, and neither end is a face.
  const int last[3] = {n[0] - periodic.wraps(0), n[1] - periodic.wraps(1), n[2] - periodic.wraps(2)};
  const auto onFace = [&](int axis, int i) { return !periodic.wraps(axis) && (i == 0 || i == n[axis]); };
  // Every lattice point with at least one coordinate on a face, minus the top face if open.
  for (int k = 0; k <= last[2]; ++k)
    for (int j = 0; j <= last[1]; ++j) {
      const bool onZ = onFace(2, k), onY = onFace(1, j);
      for (int i = 0; i <= last[0]; ++i) {
        const bool onX = onFace(0, i);
        if (!(onX || onY || onZ)) {
          if (!periodic.wraps(0)) i = n[0] - 1;  // skip the interior of this row
          continue;
        }
        if (s.openTop && !periodic.wraps(1) && j == n[1]) continue;
        out.push_back({coord(0, i), coord(1, j), coord(2, k)});
      }
    }
}

void sampleRing(const Vec3& centre, Real r, Real spacing, std::vector<Vec3>& out) {
  if (r < 0.25 * spacing) {
    out.push_back(centre);
    return;
  }
  const int n = std::max(3, int(std::lround(2 * kPi * r / spacing)));
  for (int k = 0; k < n; ++k) {
    const Real a = 2 * kPi * k / n;
    out.push_back(centre + Vec3(r * std::cos(a), 0, r * std::sin(a)));
  }
}

void sampleDisc(const Vec3& centre, Real radius, Real spacing, std::vector<Vec3>& out) {
  const int rings = divisions(radius, spacing);
  for (int k = 0; k <= rings; ++k) sampleRing(centre, radius * k / rings, spacing, out);
}

void sampleCylinder(const SolidSpec& s, Real spacing, std::vector<Vec3>& out) {
  sampleDisc(s.base, s.radius, spacing, out);
  const int layers = divisions(s.height, spacing);
  for (int k = 1; k <= layers; ++k)
    sampleRing(s.base + Vec3(0, s.height * k / layers, 0), s.radius, spacing, out);
  if (!s.openTop) sampleDisc(s.base + Vec3(0, s.height, 0), s.radius, spacing, out);
}

void sampleRevolution(const SolidSpec& s, Real spacing, std::vector<Vec3>& out) {
  const auto& pr = s.profile;
  sampleDisc(s.base + Vec3(0, pr.front().first, 0), pr.front().second, spacing, out);
  // Walk the profile polyline by arc length; one ring per step.
  for (size_t seg = 0; seg + 1 < pr.size(); ++seg) {
    const Real dy = pr[seg + 1].first - pr[seg].first, dr = pr[seg + 1].second - pr[seg].second;
    const int steps = divisions(std::hypot(dy, dr), spacing);
    for (int k = 1; k <= steps; ++k) {
      const Real t = Real(k) / steps;
      sampleRing(s.base + Vec3(0, pr[seg].first + t * dy, 0), pr[seg].second + t * dr, spacing, out);
    }
  }
  sampleDisc(s.base + Vec3(0, pr.back().first, 0), pr.back().second, spacing, out);
}

}  // namespace

std::vector<Vec3> sampleSolidSurfaces(const std::vector<SolidSpec>& solids, Real spacing, Real offset,
                                      const PeriodicDomain& periodic) {
  std::vector<Vec3> out;
  const Vec3 d(offset, offset, offset);
  for (SolidSpec s : solids) {
    // The sampled surface is the container's surface pushed outward by `offset`.
    s.min -= d;
    s.max += d;
    for (int a = 0; a < 3; ++a)
      if (periodic.wraps(a) && s.shape == SolidSpec::Shape::Box) {
        s.min[a] = periodic.lo[a];
        s.max[a] = periodic.lo[a] + periodic.length[a];
      }
    s.radius += offset;
    s.base.y -= offset;
    s.height += 2 * offset;
    for (auto& pt : s.profile) pt.second += offset;
    if (!s.profile.empty()) s.profile.back().first += 2 * offset;
    switch (s.shape) {
      case SolidSpec::Shape::Box: sampleBox(s, spacing, periodic, out); break;
      case SolidSpec::Shape::Cylinder: sampleCylinder(s, spacing, out); break;
      case SolidSpec::Shape::Revolution: sampleRevolution(s, spacing, out); break;
    }
  }
  if (periodic.any())
    out.erase(std::remove_if(out.begin(), out.end(), [&](const Vec3& p) {
                for (int a = 0; a < 3; ++a)
                  if (periodic.wraps(a) && !(p[a] >= periodic.lo[a] && p[a] < periodic.lo[a] + periodic.length[a])) return true;
                return false;
              }), out.end());
  return out;
}

BoundarySamples makeBoundarySamples(std::vector<Vec3> positions, const SphKernels& kernels,
                                    const Vec3& gridOrigin, Real volumeScale, const PeriodicDomain& periodic) {
  BoundarySamples b;
  b.position = std::move(positions);
  b.volume.assign(b.size(), 0);
  if (b.size() == 0) return b;
  CellGrid grid;
  grid.build(b.position.data(), b.size(), gridOrigin, kernels.h);
  NeighborLists nl;
  grid.findNeighbors(grid, kernels.h, false, nl, periodic);
  tbb::parallel_for(size_t(0), b.size(), [&](size_t i) {
    Real sum = 0;
    for (uint64_t k = nl.begin(i); k < nl.end(i); ++k)
      sum += kernels.densityChecked(lengthSquared(periodic.separation(b.position[i], b.position[nl.indices[k]])));
    b.volume[i] = volumeScale / sum;  // sum includes the sample itself, so it is > 0
  });
  return b;
}

Real wallSampleOffset(const SphKernels& K, Real s, Real b) {
  const int nf = int(std::ceil(K.h / s)) + 1, nb = int(std::ceil(K.h / b)) + 1;
  // Density of the first fluid layer (at z = s/2 above the surface) from the fluid half-lattice,
  // relative to a full lattice.
  Real full = 0, half = 0;
  for (int k = -nf; k <= nf; ++k)
    for (int j = -nf; j <= nf; ++j)
      for (int i = -nf; i <= nf; ++i) {
        const int r2 = i * i + j * j + k * k;
        const Real w = r2 == 0 ? K.selfWeight : K.densityChecked(s * s * Real(r2));
        full += w;
        if (k >= 0) half += w;
      }
  const Real missing = 1 - half / full;
  // One wall layer at depth `offset` below the surface: contribution sum_b V_b W, V_b = 1/sum_k W_bk.
  Real layerAtSelf = 0;
  for (int j = -nb; j <= nb; ++j)
    for (int i = -nb; i <= nb; ++i) layerAtSelf += K.densityChecked(b * b * Real(i * i + j * j));
  auto wallContribution = [&](Real offset) {
    const Real dz = 0.5 * s + offset;
    Real sum = 0;
    for (int j = -nb; j <= nb; ++j)
      for (int i = -nb; i <= nb; ++i) sum += K.densityChecked(b * b * Real(i * i + j * j) + dz * dz);
    return sum / layerAtSelf;
  };
  Real lo = 0, hi = K.h;  // contribution falls monotonically with the offset
  if (wallContribution(lo) <= missing) return 0;
  for (int it = 0; it < 60; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (wallContribution(mid) > missing ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

WallCalibration calibrateImplicitWall(const SphKernels& K, Real s, Real b) {
  const int nf = int(std::ceil(K.h / s)) + 1, nb = int(std::ceil(K.h / b)) + 1;
  // The seeding lattice around a first-layer particle; x_i - x_j = -(i, j, k) s.
  Real latticeSum = 0, present = 0, fluidPush = 0;
  for (int k = -nf; k <= nf; ++k)
    for (int j = -nf; j <= nf; ++j)
      for (int i = -nf; i <= nf; ++i) {
        const int r2 = i * i + j * j + k * k;
        const Real w = r2 == 0 ? K.selfWeight : K.densityChecked(s * s * Real(r2));
        latticeSum += w;
        if (k < 0) continue;
        present += w;
        if (r2 > 0) fluidPush += K.pressureGrad(Vec3(-i * s, -j * s, -k * s), s * s * Real(r2)).z;
      }
  // What the missing half-lattice gives the first layer: its density, and (the pair force
  // counting p_i + p_j) twice its gradient under a uniform pressure.
  const Real missing = 1 - present / latticeSum, push = -2 * fluidPush / latticeSum;
  // One sample layer at distance dz, unit Akinci volumes: density and push (z components).
  Real layerAtSelf = 0;
  for (int j = -nb; j <= nb; ++j)
    for (int i = -nb; i <= nb; ++i) layerAtSelf += K.densityChecked(b * b * Real(i * i + j * j));
  auto layer = [&](Real dz, bool gradient) {
    Real sum = 0;
    for (int j = -nb; j <= nb; ++j)
      for (int i = -nb; i <= nb; ++i) {
        const Real r2 = b * b * Real(i * i + j * j) + dz * dz;
        if (r2 < K.h2) sum += gradient ? K.pressureGrad(Vec3(-i * b, -j * b, dz), r2).z : K.density(r2);
      }
    return sum / layerAtSelf;
  };
  // The layer's push per density, seen from the first fluid layer, steepens as the layer sinks
  // towards the edge of the support: bisect its depth for push / missing.
  const Real target = std::fabs(push / missing), first = 0.5 * s;
  auto steepness = [&](Real depth) { return std::fabs(layer(depth + first, true) / layer(depth + first, false)); };
  Real lo = 0, hi = K.h - first;
  for (int it = 0; it < 60; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (steepness(mid) < target ? lo : hi) = mid;
  }
  WallCalibration c;
  c.offset = 0.5 * (lo + hi);
  c.volumeScale = missing / layer(c.offset + first, false);
  // Where a lone particle reads rest density: the wall's density falls with the height.
  const Real lone = 1 - K.selfWeight / latticeSum;
  lo = -c.offset, hi = first;
  for (int it = 0; it < 60; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (c.volumeScale * layer(c.offset + mid, false) > lone ? lo : hi) = mid;
  }
  c.contactHeight = 0.5 * (lo + hi);
  return c;
}

Real profileRadius(const SolidSpec& s, Real y) {
  const auto& pr = s.profile;
  if (y <= pr.front().first) return pr.front().second;
  for (size_t k = 0; k + 1 < pr.size(); ++k)
    if (y <= pr[k + 1].first) {
      const Real t = (y - pr[k].first) / (pr[k + 1].first - pr[k].first);
      return pr[k].second + t * (pr[k + 1].second - pr[k].second);
    }
  return pr.back().second;
}

bool insideFluidRegion(const SolidSpec& s, const Vec3& p, Real m) {
  switch (s.shape) {
    case SolidSpec::Shape::Box:
      return p.x >= s.min.x - m && p.x <= s.max.x + m && p.y >= s.min.y - m && (s.openTop || p.y <= s.max.y + m) &&
             p.z >= s.min.z - m && p.z <= s.max.z + m;
    case SolidSpec::Shape::Cylinder: {
      const Real dx = p.x - s.base.x, dz = p.z - s.base.z, y = p.y - s.base.y, r = s.radius + m;
      return y >= -m && (s.openTop || y <= s.height + m) && dx * dx + dz * dz <= r * r;
    }
    case SolidSpec::Shape::Revolution: {
      const Real dx = p.x - s.base.x, dz = p.z - s.base.z, y = p.y - s.base.y;
      if (y < s.profile.front().first - m || y > s.profile.back().first + m) return false;
      const Real r = profileRadius(s, y) + m;
      return dx * dx + dz * dz <= r * r;
    }
  }
  return true;
}

bool aboveOpenTop(const SolidSpec& s, const Vec3& p) {
  if (!s.openTop) return false;
  switch (s.shape) {
    case SolidSpec::Shape::Box: return p.y > s.max.y;
    case SolidSpec::Shape::Cylinder: return p.y > s.base.y + s.height;
    case SolidSpec::Shape::Revolution: return false;  // always closed
  }
  return false;
}

namespace {

// Keeps radial distance from the axis at most rmax; removes outward radial velocity.
bool clampRadial(const Vec3& axisPoint, Real rmax, Vec3& p, Vec3& v) {
  const Real dx = p.x - axisPoint.x, dz = p.z - axisPoint.z;
  const Real r2 = dx * dx + dz * dz;
  if (r2 <= rmax * rmax) return false;
  const Real r = std::sqrt(r2);
  const Real nx = dx / r, nz = dz / r;
  const Real target = rmax * (1 - 1e-9);  // strictly inside after rounding
  p.x = axisPoint.x + nx * target;
  p.z = axisPoint.z + nz * target;
  const Real vn = v.x * nx + v.z * nz;
  if (vn > 0) {
    v.x -= vn * nx;
    v.z -= vn * nz;
  }
  return true;
}

bool clampAxis(Real lo, Real hi, bool clampHi, Real& p, Real& v) {
  if (p < lo) {
    p = lo;
    if (v < 0) v = 0;
    return true;
  }
  if (clampHi && p > hi) {
    p = hi;
    if (v > 0) v = 0;
    return true;
  }
  return false;
}

}  // namespace

bool clampToFluidRegion(const SolidSpec& s, Vec3& p, Vec3& v) {
  bool moved = false;
  switch (s.shape) {
    case SolidSpec::Shape::Box:
      moved |= clampAxis(s.min.x, s.max.x, true, p.x, v.x);
      moved |= clampAxis(s.min.y, s.max.y, !s.openTop, p.y, v.y);
      moved |= clampAxis(s.min.z, s.max.z, true, p.z, v.z);
      break;
    case SolidSpec::Shape::Cylinder:
      moved |= clampAxis(s.base.y, s.base.y + s.height, !s.openTop, p.y, v.y);
      moved |= clampRadial(s.base, s.radius, p, v);
      break;
    case SolidSpec::Shape::Revolution:
      moved |= clampAxis(s.base.y + s.profile.front().first, s.base.y + s.profile.back().first, true,
                         p.y, v.y);
      moved |= clampRadial(s.base, profileRadius(s, p.y - s.base.y), p, v);
      break;
  }
  return moved;
}

}  // namespace mf
