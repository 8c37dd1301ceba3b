// The DFSPH step of Simulation (Bender & Koschier 2017, Algorithm 1), with several fluids in one
// solve through the density contrast constraint (sim/pressure/dfsph.h):
//   non-pressure forces -> dt from the flow -> v* = v + dt F/m -> constant-density solve on v*
//   -> x += dt v* -> neighbours, density, D_i -> divergence-free solve on v.
// Positions that would leave a container are still put back on the wall and counted; with the
// walls inside the solve that count is what the clamp-free walls are measured by.
#include <fmt/format.h>

#include "parallel_util.h"
#include "pressure/dfsph.h"
#include "simulation.h"

namespace mf {

Real Simulation::stepDfsph(Real maxDt) {
  accumulateForces();  // every effect but pressure: the solver is the pressure force
  Real dt = std::min(chooseDt(), maxDt);
  savedPosition_ = ps_.position;
  savedVelocity_ = ps_.velocity;
  const std::vector<Real> savedPressure = ps_.pressure, savedDivergence = ps_.divergencePressure;
  for (int attempt = 0;; ++attempt) {
    accelerate(dt, savedVelocity_);  // v* from the non-pressure forces
    const auto t0 = Clock::now();
    const PressureSolveStats density = dfsph_->solveDensity(context(), ps_, dt);
    times_.pressure += since(t0);
    advect(dt, savedPosition_);
    searchAndDensity();
    const auto t1 = Clock::now();
    const PressureSolveStats divergence = dfsph_->solveDivergence(context(), ps_, dt);
    times_.pressure += since(t1);
    counters_.pressureIterations += uint64_t(density.iterations);
    counters_.divergenceIterations += uint64_t(divergence.iterations);
    std::string why, parameter;
    int64_t bad = findInvalidParticle(dt, why, parameter);
    if (bad < 0 && !density.converged) {
      why = fmt::format("the constant-density solve did not converge in {} iterations (mean density error {:.3g} %, max {:.3g} %)",
                        density.iterations, 100 * density.meanError, 100 * density.maxError);
      parameter = "solver.cfl (a smaller step), solver.max_pressure_iterations or solver.density_tolerance";
    }
    if (bad < 0 && density.converged) {
      counters_.lastDensityError = density.meanError;
      counters_.lastDivergenceError = divergence.meanError;
      return dt;
    }
    ps_.pressure = savedPressure;
    ps_.divergencePressure = savedDivergence;
    retryOrStop(attempt, dt, bad, why, parameter);
    dt *= 0.5;
  }
}

}  // namespace mf
