// The interface every physical effect implements (SPlisHSPlasH-style): a scene enables effects
// by name, the step loop calls only those, and knows nothing about what they model.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
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
  // The grids behind the lists (built from the positions of the step's move; DFSPH's passes on
  // compression move particles by a small part of a spacing after it), for effects that must look
  // around points that are not particles (where a new particle would go): build a CellGrid of
  // the points with `gridOrigin` and h, and call its findNeighbors against these.
  const CellGrid* fluidGrid = nullptr;
  const CellGrid* boundaryGrid = nullptr;  // null when the scene has no solids
  Vec3 gridOrigin;
  Real particleSpacing = 0;
  // Pair separations: x_i - x_j is periodic.separation(x_i, x_j) (the nearest image); it is
  // plain subtraction, bit for bit, when no axis wraps. Pass it to findNeighbors too.
  PeriodicDomain periodic;
  // Per phase, the added density of its inertia (PhaseSpec::addedDensity); null where no phase has one.
  const std::vector<Real>* addedDensity = nullptr;
};

/// The density particle i's inertia has: its rest density plus its phase's added density. Every
/// force and the pressure accelerate it by 1 / (this V); its weight stays m g.
inline Real inertialDensity(const StepContext& ctx, const ParticleSet& ps, size_t i) {
  return ctx.addedDensity ? ps.restDensity[i] + (*ctx.addedDensity)[ps.phase[i]] : ps.restDensity[i];
}
/// The mass forces accelerate: m (rho0 + added) / rho0.
inline Real inertialMass(const StepContext& ctx, const ParticleSet& ps, size_t i) {
  return ctx.addedDensity ? ps.mass[i] * (inertialDensity(ctx, ps, i) / ps.restDensity[i]) : ps.mass[i];
}

/// Births and removals that effects ask for after an accepted step. The simulation applies them
/// once all effects have decided, on the same state: removals keep the order (and ids) of the
/// survivors, births are appended in the order given and get ids from the simulation's counter,
/// which only grows (stored in checkpoints), so an id is never reused. For the same bits on any
/// thread count an effect must fill `births` in an order that does not depend on threads (e.g.
/// decide per particle in parallel, then walk the particles in index order).
struct ParticleEdits {
  std::vector<uint8_t> remove;       // one flag per particle (size n); non-zero: remove
  std::vector<ParticleInit> births;  // new particles
  std::vector<uint32_t> bornBy;      // per birth, the index of the effect that asked (for counts)
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual const char* name() const = 0;
  /// Optional particle attributes this effect reads or writes.
  virtual AttributeMask requiredAttributes() const { return 0; }
  /// Adds this effect's force (N) to particles.force.
  virtual void accumulateForces(const StepContext& ctx, ParticleSet& particles) = 0;
  /// Implicit effects (solver.pressure = "dfsph"): correct the predicted velocities ps.velocity
  /// over dt, after the explicit forces and before the pressure solve. Returns "" or why the
  /// solve failed (the step is then retried with a smaller dt).
  virtual std::string solveVelocities(const StepContext&, ParticleSet&, Real /*dt*/) { return {}; }
  /// The largest stable time step this effect allows (s); called after accumulateForces.
  virtual Real maxTimeStep(const StepContext&, const ParticleSet&) const {
    return std::numeric_limits<Real>::infinity();
  }
  /// Advances non-mechanical state (temperature, dye, rest density) over the accepted step dt,
  /// from rates computed in accumulateForces at the step's start (explicit Euler). Called once
  /// per step after the watchdog has accepted the motion, in registry order.
  virtual void advance(const StepContext&, ParticleSet&, Real /*dt*/) {}
  /// Sets derived state once after seeding (e.g. rest density from the start temperature).
  virtual void prepare(ParticleSet&) {}

  /// True if this effect creates or removes particles (editParticles is then called).
  virtual bool editsParticles() const { return false; }
  /// Called after advance() on every accepted step: flag particles in edits.remove (never clear
  /// another effect's flag) and append to edits.births. Neighbour lists in ctx are current.
  virtual void editParticles(const StepContext&, const ParticleSet&, ParticleEdits&) {}

  /// State that is not in the particles (emitter counters, a heat exchanger's temperature):
  /// written into checkpoints and read back, so that a resumed run continues bit for bit.
  virtual std::vector<uint8_t> saveState() const { return {}; }
  virtual void loadState(const std::vector<uint8_t>&) {}

  /// Numbers worth reporting (births, removals by cause, ...), name and value.
  virtual std::vector<std::pair<std::string, double>> statistics() const { return {}; }
};

/// One parameter of an effect as the scene file gives it.
struct EffectParam {
  std::string key;
  int components = 1;         // 1 (number) or 3 (vector); or, with phaseNames > 0, that many names
  Real lo = -1e300, hi = 1e300;  // allowed range of each component, inclusive
  std::vector<Real> defaults; // empty: the key is required
  std::string unit, doc;
  int phaseNames = 0;         // 1: a phase name ("water"); 2: a pair (["water", "oil"]); stored as indices
  bool whole = false;         // a count or a choice: a fractional value is refused

  EffectParam(std::string k, int comps, Real low, Real high, std::vector<Real> defs, std::string u, std::string d,
              int names = 0, bool wholeNumber = false)
      : key(std::move(k)), components(comps), lo(low), hi(high), defaults(std::move(defs)), unit(std::move(u)),
        doc(std::move(d)), phaseNames(names), whole(wholeNumber) {}
};

/// A list of entries of an effect, [[effects.NAME.KEY]] in the scene file (heat sources, pairs).
struct EffectList {
  std::string key, doc;
  std::vector<EffectParam> params;
  /// Optional check of one entry beyond the per-key ranges: returns (key, message) problems,
  /// reported with the entry's file and line.
  std::function<std::vector<std::pair<std::string, std::string>>(const ParamValues&)> check = {};
};

struct EffectInfo {
  std::string name;
  std::string doc;
  std::vector<EffectParam> params;
  std::function<std::unique_ptr<Effect>(const EffectSpec&, const Scene&)> create;
  std::vector<EffectList> lists;
  std::vector<std::string> phaseKeys;  // [[phase]] keys this effect reads (for the reference and checks)
  /// Optional check of the whole table beyond per-key ranges (e.g. two phases that must differ):
  /// returns (key, message) problems, reported with the table's file and line.
  std::function<std::vector<std::pair<std::string, std::string>>(const EffectSpec&, const Scene&)> check = {};

  using Factory = std::function<std::unique_ptr<Effect>(const EffectSpec&, const Scene&)>;
  EffectInfo(std::string n, std::string d, std::vector<EffectParam> p, Factory c, std::vector<EffectList> l = {},
             std::vector<std::string> keys = {})
      : name(std::move(n)), doc(std::move(d)), params(std::move(p)), create(std::move(c)), lists(std::move(l)),
        phaseKeys(std::move(keys)) {}
};

/// Every effect the simulator knows, in the order the step loop runs them.
const std::vector<EffectInfo>& effectRegistry();
const EffectInfo* findEffect(const std::string& name);

}  // namespace mf
