// Divergence-free SPH (Bender & Koschier 2015, 2017) for several fluids at once: an implicit
// pressure that keeps every particle at its own rest density, whatever the density ratio.
//
// The constraint is the density contrast form (Solenthaler & Pajarola 2008; SPlisHSPlasH's
// multiphase): theta_i = rho_i / rho0_i = sum_j V_j W_ij + sum_b V_b W_ib = 1, with V_j = m_j /
// rho0_j the rest volumes and V_b the Akinci volumes of the wall samples (calibrated by
// calibrateImplicitWall, sim/solids.h). A light particle next to a heavy one sees the heavy one's
// volume, not its mass, so interfaces stay sharp at 1:1000. The pressure acceleration is the
// antisymmetric pair form
//   a_i = -(1/rho0_i) [ sum_j V_j (p_i + p_j) grad W_ij + sum_b V_b p_i grad W_ib ]
// so F_i = m_i a_i conserves momentum between fluid particles, and each term is -lambda times
// the gradient of a term of the constraint: the force does no work over a closed path. The wall
// samples' depth and volumes (calibrateImplicitWall) make a uniform pressure push the first layer
// off the wall as hard as the fluid pushes it on. Its diagonal, with all other pressures zero,
// gives the Jacobi step of both solves:
//   D_i = |sum_j V_j grad W_ij + sum_b V_b grad W_ib|^2 / rho0_i + V_i sum_j V_j |grad W_ij|^2 / rho0_j
//   constant density:  p_i += (theta*_i - 1) / (dt^2 D_i),  theta*_i = theta_i + dt d(theta_i)/dt
//   divergence-free:   p_i += d(theta_i)/dt / (dt D_i)
// grad W is the pressure force's gradient (lattice-normalised, sim/kernels.h), in the force and in
// d(theta)/dt alike, so that the two operators are adjoint and a linear pressure field balances
// gravity exactly on the lattice. Each pressure is kept >= 0 (a free surface pulls nothing). Both solves start from the last
// step's pressures (warm start, kept in the particles so that re-sorting and checkpoints carry
// them), iterate at least twice, and stop when the mean density error is below
// `density_tolerance` (relative) and the mean divergence error times dt below
// `divergence_tolerance`. The few particles whose predicted compression is then still over 20
// tolerances are taken by sweeps over their own neighbourhood (sweepWorst), not over the whole
// fluid. Where a particle still ends a move compressed past `solver.max_compression`, the
// simulation solves again, locally, at the positions reached (solveCompression) and redoes the
// move. Sums over particles run in fixed blocks and the local sweeps' regions are built in index
// order, so the bits do not depend on the number of threads.
#pragma once

#include <string>

#include "sim/effect.h"
#include "sim/hydrostatic_reference.h"
#include "sim/particles.h"

namespace mf {

struct DfsphSettings {
  Real densityTolerance = 5e-4;     // mean (theta* - 1), relative: 0.05 %
  Real divergenceTolerance = 1e-3;  // mean d(theta)/dt * dt: 0.1 % per step
  int maxIterations = 100;
  int minIterations = 2;
  bool conjugateGradient = true;  // else projected Jacobi
  HydrostaticReference reference;  // of the constant-density solve
};

struct PressureSolveStats {
  int iterations = 0;
  Real meanError = 0;  // relative density (or divergence x dt) error at the end
  Real maxError = 0;
  bool converged = true;
};

class DfsphSolver {
 public:
  explicit DfsphSolver(const DfsphSettings& settings) : settings_(settings) {}

  /// D_i of the current positions, and the pairs' kernel gradients the solves reuse; call after
  /// every neighbour search and density pass.
  /// `only`: the listed particles alone (after a move of some of them).
  void computeDiagonal(const StepContext& ctx, const ParticleSet& ps, const std::vector<uint32_t>* only = nullptr);
  /// Corrects the predicted velocities ps.velocity so that positions advanced by dt are at rest
  /// density; the pressure used stays in ps.pressure (Pa).
  PressureSolveStats solveDensity(const StepContext& ctx, ParticleSet& ps, Real dt);
  /// Corrects ps.velocity so that the density does not change (d theta / dt = 0) where the fluid
  /// is at rest density; its pressure is kept in ps.divergencePressure.
  PressureSolveStats solveDivergence(const StepContext& ctx, ParticleSet& ps, Real dt);

  /// The constant-density solve once more, at the positions the move reached: one Gauss-Newton
  /// step on theta(x) = 1. The solve above is linear in the move, and underestimates a close
  /// approach (a jet into a wall corner leaves a particle tens of per cent compressed). Finds a
  /// velocity change u, from pressures dp >= 0 that start at zero, that leaves no particle's
  /// theta + dt d(theta)/dt(u) - 1 over `target`, and returns it in `u`;
  /// ps.velocity and ps.pressure are left as they were. The solve is local: its unknowns are the
  /// particles past the target and their neighbours (a handful of the fluid: the mean error is
  /// the first solve's), so its sweeps run over those and the velocities they change, and
  /// `moved` lists the latter (sorted); u is zero elsewhere.
  PressureSolveStats solveCompression(const StepContext& ctx, ParticleSet& ps, Real dt, Real target, std::vector<Vec3>& u,
                                      std::vector<uint32_t>& moved);

  const DfsphSettings& settings() const { return settings_; }

 private:
  /// Projected Jacobi on the particles whose error (theta + dt d(theta)/dt of `velocity`, minus
  /// 1; `initialError(i)` before the first sweep) is past `worst`, and their neighbours: the
  /// unknowns' pressures `p` (>= lower_) change the velocities of the unknowns and their
  /// neighbours, listed in `moved`, and nothing else, so each sweep costs what that
  /// neighbourhood costs. Until no unknown is past `worst`; the sweeps add to stats.iterations.
  template <class InitialError>
  void sweepWorst(const StepContext& ctx, const ParticleSet& ps, std::vector<Real>& p, std::vector<Vec3>& velocity, Real dt,
                  Real worst, InitialError&& initialError, std::vector<uint32_t>& moved, PressureSolveStats& stats);
  /// Where a solve stops: the mean error, and the worst particle's.
  struct Tolerance {
    Real mean, worst;
  };
  Tolerance densityTolerance() const;
  /// theta*_i - 1, theta* = theta + dt d(theta)/dt: the density the move would leave, from the
  /// last densityRate (rate_).
  Real densityError(const ParticleSet& ps, Real dt, size_t i) const {
    return ps.density[i] / ps.restDensity[i] + dt * rate_[i] - 1;
  }
  /// d theta_i / dt of `velocity` (fluid pairs and walls), for particle i; densityRate for all.
  Real rateOf(const StepContext& ctx, const std::vector<Vec3>& velocity, size_t i) const;
  void densityRate(const StepContext& ctx, const std::vector<Vec3>& velocity, std::vector<Real>& rate) const;
  /// dt a_i for the pressure field `p` (the acceleration above); applyPressure subtracts it from
  /// every velocity.
  Vec3 velocityChange(const StepContext& ctx, const ParticleSet& ps, const std::vector<Real>& p, Real dt, size_t i) const;
  void applyPressure(const StepContext& ctx, const ParticleSet& ps, const std::vector<Real>& p, Real dt,
                     std::vector<Vec3>& velocity) const;
  /// One projected, relaxed Jacobi update of particle i's pressure p for its error.
  Real jacobiPressure(size_t i, Real p, Real error, Real stepScale) const;
  /// What both solves share: the warm start, then projected Jacobi, or (conjugateGradient)
  /// Jacobi sweeps while they converge fast and CG on the rest.
  template <class Error>
  PressureSolveStats solve(const StepContext& ctx, ParticleSet& ps, std::vector<Real>& p, Real dt, Real stepScale,
                           Real errorScale, const Tolerance& tolerance, Error&& error);

  /// Jacobi iterations: p_i += omega error_i stepScale / D_i (kept >= 0) until the mean |error| x
  /// errorScale is below `tolerance`, or (not converged) a sweep leaves more than `stallRatio` of
  /// the error before it.
  /// The stop both iterations share: at least minIterations, the mean and the worst error within
  /// `tolerance`.
  bool converged(int used, const PressureSolveStats& s, const Tolerance& tolerance) const;

  template <class Error>
  PressureSolveStats iterate(const StepContext& ctx, ParticleSet& ps, std::vector<Real>& p, Real dt, Real stepScale,
                             Real errorScale, const Tolerance& tolerance, Real stallRatio, Error&& error);

  /// The same solve by Jacobi-preconditioned conjugate gradients on the active set (the particles
  /// that carry a pressure or are compressed), projected to p >= 0 between restarts; `used`
  /// iterations are already spent.
  template <class Error>
  PressureSolveStats iterateCg(const StepContext& ctx, ParticleSet& ps, std::vector<Real>& p, Real dt, Real stepScale,
                               Real errorScale, const Tolerance& tolerance, int used, Error&& error);

  DfsphSettings settings_;
  std::vector<Real> err_, x_, r_, z_, d_, q_;
  std::vector<char> active_;
  std::vector<Vec3> scratchVelocity_;
  std::vector<Real> correctionPressure_;
  std::vector<char> region_;  // sweepWorst's region: 3 past the bound, 2 unknown, 1 moved by them
  std::vector<uint32_t> unknowns_, worstMoved_;
  std::vector<Real> localError_;
  std::vector<Real> diagonal_, rate_, delta_;
  std::vector<Real> restVolume_;  // m / rho0 per particle, so that the pair loop divides once per particle
  std::vector<Real> lower_;  // the least pressure each particle may hold (0, or -p_ref)
  // V grad W per neighbour pair, from computeDiagonal, in single precision: the sweeps stream
  // them once per iteration, and half the bytes took 15 % off the reference dam break's run.
  struct GradF {
    float x, y, z;
    static GradF of(const Vec3& v) { return {float(v.x), float(v.y), float(v.z)}; }
    Vec3 vec() const { return {x, y, z}; }
  };
  std::vector<GradF> fluidGrad_, wallGrad_;
};

}  // namespace mf
