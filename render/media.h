// Dielectric boundaries and nested volumes: Fresnel reflectance, and the stack of volumes a ray
// is inside, resolved by priority (Schmidt & Budge 2002, as production renderers resolve
// overlapping volumes such as water against the glass that holds it).
#pragma once

#include <vector>

#include "settings.h"

namespace mf::render {

/// Unpolarised Fresnel reflectance for a dielectric interface.
inline Real fresnel(Real cosi, Real cost, Real n1, Real n2) {
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

}  // namespace mf::render
