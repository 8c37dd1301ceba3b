// The interface every physical effect implements (SPlisHSPlasH-style): a scene enables effects
// by name, the step loop calls only those, and knows nothing about what they model.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "kernels.h"
#include "neighbor_search.h"
#include "particles.h"
#include "scene.h"

namespace mf {

/// Static boundary samples (Akinci et al. 2012): positions and volumes Vb = 1 / sum_k W_bk.
struct BoundarySamples {
  std::vector<Vec3> position;
  std::vector<Real> volume;
  size_t size() const { return position.size(); }
};

/// Read-only view of the step's shared data, passed to every effect.
struct StepContext {
  const SphKernels& kernels;
  const NeighborLists& fluidNeighbors;     // fluid-fluid, rows per particle
  const NeighborLists& boundaryNeighbors;  // fluid-boundary, rows per particle
  const BoundarySamples& boundary;
  Real time;
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual const char* name() const = 0;
  /// Optional particle attributes this effect reads or writes.
  virtual AttributeMask requiredAttributes() const { return 0; }
  /// Adds this effect's force (N) to particles.force.
  virtual void accumulateForces(const StepContext& ctx, ParticleSet& particles) = 0;
  /// The largest stable time step this effect allows (s).
  virtual Real maxTimeStep(const StepContext&, const ParticleSet&) const {
    return std::numeric_limits<Real>::infinity();
  }
};

/// One parameter of an effect as the scene file gives it.
struct EffectParam {
  std::string key;
  int components = 1;         // 1 (number) or 3 (vector)
  Real lo = -1e300, hi = 1e300;  // allowed range of each component, inclusive
  std::vector<Real> defaults;
  std::string unit, doc;
};

struct EffectInfo {
  std::string name;
  std::string doc;
  std::vector<EffectParam> params;
  std::function<std::unique_ptr<Effect>(const EffectSpec&, const Scene&)> create;
};

/// Every effect the simulator knows, in the order the step loop runs them.
const std::vector<EffectInfo>& effectRegistry();
const EffectInfo* findEffect(const std::string& name);

}  // namespace mf
