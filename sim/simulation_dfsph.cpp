// The DFSPH step of Simulation (Bender & Koschier 2017, Algorithm 1), with several fluids in one
// solve through the density contrast constraint (sim/pressure/dfsph.h):
//   non-pressure forces -> dt from the flow -> v* = v + dt F/m -> constant-density solve on v*
//   -> x += dt v* -> neighbours, density, D_i -> divergence-free solve on v.
// Positions that would leave a container are still put back on the wall and counted; with the
// walls inside the solve that count is what the clamp-free walls are measured by.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "parallel_util.h"
#include "pressure/dfsph.h"
#include "simulation.h"

namespace mf {

namespace {
// Gauss-Newton passes on the move's compression per step. Each aims at half the bound
// (solver.max_compression), so that what the move adds beyond the linear prediction stays under
// it; a pass costs only the neighbourhood it corrects. On the reference dam break at the 1 % bound
// three passes left a particle at 1.10 %, five at 0.99 %.
constexpr int kCompressionPasses = 5;
}

void Simulation::seedHydrostaticPressure() {
  // The solver's warm start begins at the weight of the fluid above each particle, p_i = |g|
  // (sum of m_j / s^2 over its lattice column above, plus half its own), so a fluid seeded at
  // rest starts in hydrostatic balance instead of falling for the first steps while Jacobi
  // carries the pressure up from the floor. Only a guess: the solve still sets the pressure.
  Vec3 g;  // gravity at t = 0: none while it is ramped in
  for (const EffectSpec& e : scene_.effects)
    if (e.name == "gravity" && e.number("ramp_time") == 0) g = e.vector("acceleration");
  const Real gn = length(g), s = scene_.solver.particleSpacing;
  if (gn == 0 || ps_.size() == 0) return;
  const Vec3 up = g * (-1 / gn);
  // Two axes across gravity name a column; the height along `up` orders it.
  const Vec3 a = std::fabs(up.x) < 0.9 ? normalize(cross(up, Vec3(1, 0, 0))) : normalize(cross(up, Vec3(0, 1, 0)));
  const Vec3 b = cross(up, a);
  struct Entry {
    int64_t u, v;
    Real height;
    size_t index;
  };
  std::vector<Entry> order(ps_.size());
  for (size_t i = 0; i < ps_.size(); ++i) {
    const Vec3 x = ps_.position[i];
    order[i] = {std::llround(dot(x, a) / s), std::llround(dot(x, b) / s), dot(x, up), i};
  }
  std::sort(order.begin(), order.end(), [](const Entry& l, const Entry& r) {
    if (l.u != r.u) return l.u < r.u;
    if (l.v != r.v) return l.v < r.v;
    if (l.height != r.height) return l.height > r.height;
    return l.index < r.index;
  });
  const Real perArea = gn / (s * s);
  for (size_t k = 0; k < order.size();) {
    Real above = 0;
    size_t e = k;
    for (; e < order.size() && order[e].u == order[k].u && order[e].v == order[k].v; ++e) {
      const Real m = ps_.mass[order[e].index];
      ps_.pressure[order[e].index] = perArea * (above + 0.5 * m);
      above += m;
    }
    k = e;
  }
}

Real Simulation::stepDfsph(Real maxDt) {
  accumulateForces();  // every effect but pressure: the solver is the pressure force
  // The constant-density solve removes the compression a step starts with within that step, so
  // the velocity it leaves grows as 1/dt: a sliver of a step before a frame's time turned a
  // particle's 4 % compression against a wall into 11 m/s. Where the time allowed is under two
  // flow steps, take half of it, so that a frame's last steps are at least half a flow step.
  Real dt = evenStep(maxDt, chooseDt());
  snapshotStep();
  const std::vector<Real> savedPressure = ps_.pressure, savedDivergence = ps_.divergencePressure;
  for (int attempt = 0;; ++attempt) {
    accelerate(dt, savedVelocity_);  // v* from the non-pressure forces
    std::string implicitFailure;     // then the implicit ones (viscosity)
    for (size_t k = 0; k < effects_.size() && implicitFailure.empty(); ++k) {
      const auto e0 = Clock::now();
      implicitFailure = effects_[k]->solveVelocities(context(), ps_, dt);
      if (!implicitFailure.empty()) implicitFailure = fmt::format("{}: {}", effects_[k]->name(), implicitFailure);
      times_.effect[k] += since(e0);
    }
    const auto t0 = Clock::now();
    const PressureSolveStats density = dfsph_->solveDensity(context(), ps_, dt);
    times_.pressure += since(t0);
    advect(dt, savedPosition_);
    searchAndDensity();
    // The solve above is linear in the move; where a particle still ends compressed past its
    // bound, solve again at the positions reached and redo the move with the corrected velocity.
    for (int pass = 0; pass < kCompressionPasses && density.converged && ps_.largestCompression() > scene_.solver.maxCompression;
         ++pass) {
      const auto c0 = Clock::now();
      const PressureSolveStats correction = dfsph_->solveCompression(context(), ps_, dt, 0.5 * scene_.solver.maxCompression,
                                                                     compressionVelocity_, compressionMoved_);
      times_.pressure += since(c0);
      counters_.pressureIterations += uint64_t(correction.iterations);
      ++counters_.compressionPasses;
      for (uint32_t i : compressionMoved_) ps_.velocity[i] += compressionVelocity_[i];
      advect(dt, savedPosition_);
      // The correction moves particles by a small part of a spacing: the move's neighbour lists
      // still hold every pair that matters (a pair entering the support adds a kernel value and
      // gradient that vanish at h to second order), so the density is summed over them again,
      // where the correction moved something.
      densityNear(compressionMoved_);
    }
    const auto t1 = Clock::now();
    const PressureSolveStats divergence = dfsph_->solveDivergence(context(), ps_, dt);
    times_.pressure += since(t1);
    counters_.pressureIterations += uint64_t(density.iterations);
    counters_.divergenceIterations += uint64_t(divergence.iterations);
    std::string why, parameter;
    int64_t bad = findInvalidParticle(dt, why, parameter);
    if (bad < 0 && !implicitFailure.empty()) {
      why = implicitFailure;
      parameter = "solver.cfl or solver.max_dt (a smaller step)";
    }
    if (bad < 0 && implicitFailure.empty() && !density.converged) {
      why = fmt::format("the constant-density solve did not converge in {} iterations (mean density error {:.3g} %, max {:.3g} %)",
                        density.iterations, 100 * density.meanError, 100 * density.maxError);
      parameter = "solver.cfl (a smaller step), solver.max_pressure_iterations or solver.density_tolerance";
    }
    if (bad < 0 && implicitFailure.empty() && density.converged) {
      counters_.lastDensityError = density.meanError;
      counters_.lastDivergenceError = divergence.meanError;
      return dt;
    }
    // A constant-density solve that ran out of iterations has still come nearer the answer (it
    // is what left a particle invalid, if one is): the retry goes on from its pressure instead of
    // redoing that work from the step's start. A large fluid's first steps need more iterations
    // than the cap while the solve turns the seeded column pressure into the flow's.
    const bool keepPressure = implicitFailure.empty() && !density.converged &&
                              std::all_of(ps_.pressure.begin(), ps_.pressure.end(), [](Real p) { return std::isfinite(p); });
    if (!keepPressure) ps_.pressure = savedPressure;
    ps_.divergencePressure = savedDivergence;
    try {
      retryOrStop(attempt, dt, bad, why, parameter);
    } catch (const NumericalInstability&) {
      ps_.pressure = savedPressure;  // a stopped run is left as the step found it
      throw;
    }
    dt *= 0.5;
  }
}

}  // namespace mf
