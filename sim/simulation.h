// The step loop: neighbour search, density (eq. 1 or number density), state equation, the
// scene's enabled effects, symplectic Euler with adaptive dt, and a watchdog that retries a bad
// step with a smaller dt or stops with a message naming the step, particle, phase and parameter.
// It knows no scene: what happens to particles is decided by the effects a scene enables.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "effect.h"
#include "kernels.h"
#include "neighbor_search.h"
#include "particles.h"
#include "scene.h"

namespace mf {

/// Thrown when the watchdog gives up on a step. The simulation is left at the last valid state.
class NumericalInstability : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SimulationCounters {
  uint64_t steps = 0;
  uint64_t retries = 0;            // steps redone with half the dt by the watchdog
  uint64_t removedOutOfDomain = 0; // particles that left the domain box
  uint64_t wallClamps = 0;         // particles put back inside a container by the position clamp
  uint64_t born = 0;               // particles created by effects (emitters, trapped air)
  uint64_t removedByEffects = 0;   // particles removed by effects (sinks, air deletion, vapour leaving)
  Real lastDt = 0;
  Real maxDensityError = 0;        // largest (rho - rho0)/rho0 seen after any accepted step
  // DFSPH (solver.pressure = "dfsph"): Jacobi iterations of the two solves, summed over steps,
  // and the last step's mean errors after them.
  uint64_t pressureIterations = 0, divergenceIterations = 0;
  uint64_t compressionPasses = 0;  // constant-density solves redone at the moved positions
  Real lastDensityError = 0, lastDivergenceError = 0;
};

/// Wall-clock seconds spent in each part of the step (not part of the checkpointed state).
struct StageTimes {
  double neighborSearch = 0;  // grid build + neighbour lists (includes re-sorts and retries)
  double density = 0;         // density, volume and state equation
  std::vector<double> effect; // per enabled effect, in effects() order: forces, advance, edits
  double integrate = 0;       // dt choice, integration, wall clamp, watchdog checks
  double pressure = 0;        // the implicit pressure solves (DFSPH)
  double edits = 0;           // applying births and removals: compaction, appends, new search
};

class DfsphSolver;

class Simulation {
 public:
  explicit Simulation(const Scene& scene);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  const Scene& scene() const { return scene_; }
  const ParticleSet& particles() const { return ps_; }
  /// For tests and tools that edit state; call refresh() afterwards.
  ParticleSet& mutableParticles() { return ps_; }
  /// Recomputes neighbours, density and volume for the current positions.
  void refresh();

  Real time() const { return time_; }
  uint64_t stepCount() const { return counters_.steps; }
  const SimulationCounters& counters() const { return counters_; }
  /// Per phase: particles that left the domain box, and particles effects created (checkpointed).
  const std::vector<uint64_t>& leftDomainByPhase() const { return leftDomain_; }
  const std::vector<uint64_t>& bornByPhase() const { return bornByPhase_; }
  /// Why the watchdog last retried a step, and where ("" if it never did; not checkpointed).
  const std::string& lastRetry() const { return lastRetry_; }
  /// What set the last step's dt: a solver key or an effect's name (for messages).
  const char* dtLimiter() const { return dtLimiter_; }
  const StageTimes& stageTimes() const { return times_; }
  const SphKernels& kernels() const { return kernels_; }
  /// The rest-lattice gradient moment M the pressure gradient was divided by (see the constructor).
  Real gradientMoment() const { return gradientMoment_; }
  const BoundarySamples& boundary() const { return boundary_; }
  const NeighborLists& fluidNeighbors() const { return fluidNeighbors_; }
  Real particleSpacing() const { return scene_.solver.particleSpacing; }
  /// Distance of the wall samples outside the containers' surfaces (wallSampleOffset).
  Real wallOffset() const { return wallOffset_; }
  const std::vector<std::unique_ptr<Effect>>& effects() const { return effects_; }
  /// The id the next new particle gets; ids below it were given out once and are never reused.
  uint64_t nextId() const { return nextId_; }

  /// One sub-step of at most `maxDt` seconds (the adaptive dt may be smaller); returns dt. On
  /// DFSPH, where `maxDt` is under two flow steps the step takes half of it, so that a series of
  /// steps up to a frame's time ends in two even steps, not a sliver.
  Real step(Real maxDt);
  /// Sub-steps until time() == t exactly (the last sub-steps are evened out to land on t).
  void advanceTo(Real t, const std::function<void(const Simulation&)>& afterStep = {});

  /// Exact state to a file (temporary name, then rename), with a checksum (sim/checkpoint.cpp).
  void saveCheckpoint(const std::string& path, int frame) const;
  /// Returns the frame stored in the checkpoint. Throws std::runtime_error, its text starting
  /// with `path`, for a damaged file, one of another scene or format, or values no run writes;
  /// the state is then unchanged.
  int loadCheckpoint(const std::string& path);

 private:
  void seedFluid();
  void seedHydrostaticPressure();
  /// Neighbour lists (unless `search` is false: the lists of the last search are kept), density,
  /// and the solver's diagonal at the current positions.
  void searchAndDensity(bool search = true);
  /// The density and the solver's diagonal again where a move of the `moved` particles (sorted
  /// indices) changed them, over the last search's lists: the moved particles and their neighbours.
  void densityNear(const std::vector<uint32_t>& moved);
  /// Particle i's density (and volume) over the current lists.
  void densityOf(size_t i, const PeriodicDomain& periodic);
  void computePressure();
  void accumulateForces();
  Real chooseDt() const;
  void integrate(Real dt, const std::vector<Vec3>& x0, const std::vector<Vec3>& v0);
  /// v = v0 + dt F/m (the velocity half of integrate; DFSPH's prediction).
  void accelerate(Real dt, const std::vector<Vec3>& v0);
  /// x = x0 + dt v with the container clamp (the position half of integrate).
  void advect(Real dt, const std::vector<Vec3>& x0);
  /// The watchdog's snapshot at a step's start: positions, velocities and the clamp count that
  /// every try of the step starts again from.
  void snapshotStep();
  /// The motion of one step, by the chosen pressure solver; returns the dt taken.
  Real stepWcsph(Real maxDt);
  Real stepDfsph(Real maxDt);  // Bender & Koschier 2017, Algorithm 1 (simulation_dfsph.cpp)
  /// The step toward a time `left` away when steps may be at most `limit`: all of it if it fits,
  /// half of it if two steps of `limit` would overshoot (so that none is a sliver), else `limit`.
  static Real evenStep(Real left, Real limit) { return left <= limit ? left : (left < 2 * limit ? 0.5 * left : limit); }
  /// A watchdog failure: restores the step's start and returns (the caller halves dt), or
  /// throws NumericalInstability naming the particle (bad >= 0), the step and the parameter.
  void retryOrStop(int attempt, Real dt, int64_t bad, const std::string& why, const std::string& parameter);
  /// Index of the first particle that breaks a watchdog rule, or -1; fills `why`.
  int64_t findInvalidParticle(Real dt, std::string& why, std::string& parameter) const;
  /// Outside the domain box on an axis that does not wrap: the particle is removed and counted.
  bool leavesDomain(const Vec3& x) const;
  void removeOutOfDomain();
  /// Births and removals of the effects that edit particles, and the domain check, in one pass.
  void editParticles();
  void checkInputs() const;
  StepContext context() const;

  Scene scene_;
  SphKernels kernels_;
  HalfSpaceMissing surfaceMissing_;  // solver.free_surface_completion only
  Vec3 gridOrigin_;
  std::vector<Real> addedDensity_;  // per phase, where any phase has one (StepContext::addedDensity)
  Real wallOffset_ = 0;
  std::string lastRetry_;
  ParticleSet ps_;
  BoundarySamples boundary_;
  CellGrid fluidGrid_, boundaryGrid_;
  bool listsStale_ = false;  // the lists were searched before the positions' last move (a pass)
  NeighborLists fluidNeighbors_, boundaryNeighbors_;
  std::vector<std::unique_ptr<Effect>> effects_;
  std::vector<Vec3> savedPosition_, savedVelocity_;  // watchdog snapshot
  // The clamp count before this step: each move is made again from savedPosition_ (a retry, a
  // compression pass), so the step's clamps are those of its last move, not the sum of its tries.
  uint64_t clampsBeforeStep_ = 0;
  std::vector<Vec3> compressionVelocity_;            // DFSPH's second pass on compression
  std::vector<uint32_t> compressionMoved_;           // the particles that pass moves
  std::vector<char> near_;                           // densityNear's scratch
  std::vector<uint32_t> nearList_;
  Real time_ = 0;
  uint64_t nextId_ = 0;
  SimulationCounters counters_;
  std::vector<uint64_t> leftDomain_, bornByPhase_;  // per phase
  StageTimes times_;
  Real gradientMoment_ = 1;
  mutable const char* dtLimiter_ = "solver.max_dt";  // set by chooseDt
  std::unique_ptr<DfsphSolver> dfsph_;                // solver.pressure = "dfsph" only
};

/// sum of f(i, j, k) over the integer offsets of a cubic lattice that can reach within h of
/// the origin (|i|, |j|, |k| <= ceil(h/s) + 1), in a fixed order: the one loop behind every
/// rest-lattice calibration (kernel sum, gradient moment, Laplacian moments of the effects).
template <class F>
Real sumOverRestLattice(const SphKernels& kernels, Real spacing, F&& f) {
  const int n = int(std::ceil(kernels.h / spacing)) + 1;
  Real sum = 0;
  for (int k = -n; k <= n; ++k)
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) sum += f(i, j, k);
  return sum;
}

/// The seeding lattice of a fluid block: n[a] points per axis, `spacing` apart from `start`,
/// centred in the block's box (a sphere's bounding box) half a spacing from each face. The
/// seeding and the scene budget's count (scene_budget.cpp) both walk this one lattice.
struct BlockLattice {
  int n[3] = {0, 0, 0};
  Vec3 start;
  Vec3 point(int i, int j, int k, Real spacing) const { return start + Vec3(i * spacing, j * spacing, k * spacing); }
};
BlockLattice blockLattice(const FluidBlockSpec& block, Real spacing);

/// Sum over a cubic lattice of spacing s of the density kernel within h (the centre weighted by
/// selfWeight): the
/// number density of a particle inside a uniform block. Used to give seeded particles a mass
/// so that the block starts exactly at rest density.
Real latticeKernelSum(const SphKernels& kernels, Real spacing);

/// The mass of a particle of phase `ph`: its particle_mass, or rest density / latticeKernelSum
/// (so that the seeding lattice is at rest density). Seeding and every effect that creates
/// particles use this one rule.
Real phaseParticleMass(const PhaseSpec& ph, const SphKernels& kernels, Real spacing);

/// A new particle of `phase` (index `phaseIndex`) with the given mass (phaseParticleMass), the
/// phase's material values, at x with velocity v and temperature T.
ParticleInit newParticleOfPhase(const PhaseSpec& phase, uint16_t phaseIndex, Real mass, const Vec3& x, const Vec3& v,
                                Real temperature);

/// phaseParticleMass for every phase of a scene, from its spacing and smoothing ratio (for
/// effects that create particles; they are built before the simulation's kernels exist).
std::vector<Real> phaseParticleMasses(const Scene& scene);

/// sum_j V (x_j - x_i)_y d/dy_i W over the same lattice, W the pressure force's kernel (1 for
/// an exact gradient).
Real latticeGradientMoment(const SphKernels& kernels, Real spacing);

}  // namespace mf
