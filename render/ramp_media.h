// Media whose absorption and emission come from attribute grids through colour ramps
// (render.material.NAME.absorption_ramp / emission_ramp over surfacing's <attribute>_<fluid>
// grids), integrated along a ray by the midpoint rule, one voxel per step (docs/rendering.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry.h"
#include "volume_field.h"
#include "warp.h"

namespace mf::render {

class RampMedia {
 public:
  /// The next geometry's fields: those its material's ramps read (none: its constants).
  void add(const Surface& sf) {
    const bool a = sf.absorptionField && !sf.material.absorptionRamp.empty();
    const bool e = sf.emissionField && !sf.material.emissionRamp.empty();
    absorption_.push_back(a ? sf.absorptionField.get() : nullptr);
    emission_.push_back(e ? sf.emissionField.get() : nullptr);
  }

  /// Whether geometry g's medium varies in space (else its constants hold everywhere).
  bool heterogeneous(int g) const { return absorption_[g] || emission_[g]; }

  /// Medium g's absorption and emission per metre at x: the ramps at the attributes there, or
  /// the material's constants. `m`: its material.
  void at(const MaterialSpec& m, int g, const Vec3& x, Vec3& sigma, Vec3& emit) const {
    sigma = absorption_[g] ? m.absorptionRamp.at(absorption_[g]->at(x)) : m.absorption;
    emit = emission_[g] ? m.emissionRamp.at(emission_[g]->at(x)) : m.emission;
  }

  /// Through medium g along o + t d from t = a to b: adds the emission (through `add`, times
  /// the throughput so far) and attenuates `throughput`, by the midpoint rule in steps of at
  /// most one voxel of its finest field (exact where the coefficients are linear along the ray).
  template <class Add>
  void march(const MaterialSpec& m, int g, const Vec3& o, const Vec3& d, Real a, Real b, Vec3& throughput, Add&& add) const {
    if (!(b > a)) return;
    Real step = 1e30;
    if (absorption_[g]) step = std::min(step, absorption_[g]->voxelSize());
    if (emission_[g]) step = std::min(step, emission_[g]->voxelSize());
    const int n = int(std::min(4096.0, std::ceil((b - a) / step)));
    const Real dt = (b - a) / n;
    for (int k = 0; k < n; ++k) {
      Vec3 sigma, emit;
      at(m, g, o + d * (a + (k + 0.5) * dt), sigma, emit);
      if (emit != Vec3{}) add(mul(throughput, emit) * dt);
      throughput = mul(throughput, expNeg(sigma, dt));
    }
  }

 private:
  std::vector<const VolumeField*> absorption_, emission_;  // per geometry; null: the constant
};

}  // namespace mf::render
