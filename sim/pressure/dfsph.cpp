#include "sim/pressure/dfsph.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace mf {

namespace {
constexpr size_t kBlock = 1024;
constexpr Real kRelaxation = 0.5;
}

template <class F>
Real DfsphSolver::blockSum(size_t n, F&& f) const {
  std::vector<Real> partial((n + kBlock - 1) / kBlock, 0);
  tbb::parallel_for(size_t(0), partial.size(), [&](size_t b) {
    Real s = 0;
    for (size_t i = b * kBlock, e = std::min(n, (b + 1) * kBlock); i < e; ++i) s += f(i);
    partial[b] = s;
  });
  Real total = 0;
  for (Real s : partial) total += s;  // fixed order
  return total;
}

void DfsphSolver::computeDiagonal(const StepContext& ctx, const ParticleSet& ps) {
  const size_t n = ps.size();
  const SphKernels& K = ctx.kernels;
  diagonal_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kBlock), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Vec3 xi = ps.position[i];
      Vec3 grad;
      Real others = 0;
      for (uint64_t k = ctx.fluidNeighbors.begin(i), e = ctx.fluidNeighbors.end(i); k < e; ++k) {
        const uint32_t j = ctx.fluidNeighbors.indices[k];
        const Vec3 rij = xi - ps.position[j];
        const Vec3 g = K.pressureGrad(rij, lengthSquared(rij));
        const Real Vj = ps.mass[j] / ps.restDensity[j];
        grad += g * Vj;
        others += Vj * lengthSquared(g) / ps.restDensity[j];
      }
      for (uint64_t k = ctx.boundaryNeighbors.begin(i), e = ctx.boundaryNeighbors.end(i); k < e; ++k) {
        const uint32_t b = ctx.boundaryNeighbors.indices[k];
        const Vec3 rib = xi - ctx.boundary.position[b];
        grad += K.pressureGrad(rib, lengthSquared(rib)) * ctx.boundary.volume[b];
      }
      diagonal_[i] = lengthSquared(grad) / ps.restDensity[i] + ps.mass[i] / ps.restDensity[i] * others;
    }
  });
}

void DfsphSolver::densityRate(const StepContext& ctx, const ParticleSet& ps) {
  const size_t n = ps.size();
  const SphKernels& K = ctx.kernels;
  rate_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kBlock), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Vec3 xi = ps.position[i], vi = ps.velocity[i];
      Real rate = 0;
      for (uint64_t k = ctx.fluidNeighbors.begin(i), e = ctx.fluidNeighbors.end(i); k < e; ++k) {
        const uint32_t j = ctx.fluidNeighbors.indices[k];
        const Vec3 rij = xi - ps.position[j];
        rate += ps.mass[j] / ps.restDensity[j] * dot(vi - ps.velocity[j], K.pressureGrad(rij, lengthSquared(rij)));
      }
      for (uint64_t k = ctx.boundaryNeighbors.begin(i), e = ctx.boundaryNeighbors.end(i); k < e; ++k) {
        const uint32_t b = ctx.boundaryNeighbors.indices[k];
        const Vec3 rib = xi - ctx.boundary.position[b];
        rate += ctx.boundary.volume[b] * dot(vi, K.pressureGrad(rib, lengthSquared(rib)));
      }
      rate_[i] = rate;
    }
  });
}

void DfsphSolver::applyPressure(const StepContext& ctx, ParticleSet& ps, const std::vector<Real>& p, Real dt) {
  const size_t n = ps.size();
  const SphKernels& K = ctx.kernels;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kBlock), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Vec3 xi = ps.position[i];
      const Real pi = p[i];
      Vec3 acc;
      for (uint64_t k = ctx.fluidNeighbors.begin(i), e = ctx.fluidNeighbors.end(i); k < e; ++k) {
        const uint32_t j = ctx.fluidNeighbors.indices[k];
        const Real pij = pi + p[j];
        if (pij == 0) continue;
        const Vec3 rij = xi - ps.position[j];
        acc += K.pressureGrad(rij, lengthSquared(rij)) * (ps.mass[j] / ps.restDensity[j] * pij);
      }
      if (pi != 0)
        for (uint64_t k = ctx.boundaryNeighbors.begin(i), e = ctx.boundaryNeighbors.end(i); k < e; ++k) {
          const uint32_t b = ctx.boundaryNeighbors.indices[k];
          const Vec3 rib = xi - ctx.boundary.position[b];
          acc += K.pressureGrad(rib, lengthSquared(rib)) * (ctx.boundary.volume[b] * pi);
        }
      // Velocities are read (positions only) and written per particle: no race.
      ps.velocity[i] -= acc * (dt / ps.restDensity[i]);
    }
  });
}

PressureSolveStats DfsphSolver::solveDensity(const StepContext& ctx, ParticleSet& ps, Real dt) {
  const size_t n = ps.size();
  PressureSolveStats stats;
  if (n == 0) return stats;
  std::vector<Real>& p = ps.pressure;
  // Warm start: last step's pressure (hydrostatic pressure persists from step to step).
  applyPressure(ctx, ps, p, dt);
  delta_.resize(n);
  const Real inv = 1 / (dt * dt);
  for (int it = 0; it < settings_.maxIterations; ++it) {
    densityRate(ctx, ps);
    // theta* = theta + dt d(theta)/dt; Jacobi step on the pressure, kept >= 0.
    Real maxErr = 0;
    const Real sum = blockSum(n, [&](size_t i) {
      // Projected, relaxed Jacobi: the pressure stays >= 0 (a free surface pulls nothing) and can
      // fall as well as rise, so a warm start that overshoots is undone; the half step keeps the
      // checkerboard mode of the SPH Laplacian from growing (IISPH's omega = 0.5).
      const Real err = ps.density[i] / ps.restDensity[i] + dt * rate_[i] - 1;
      const Real next = diagonal_[i] > 0 ? std::max(Real(0), p[i] + kRelaxation * err * inv / diagonal_[i]) : Real(0);
      delta_[i] = next - p[i];
      // The error left: compression anywhere, and expansion where a pressure still pushes.
      return next > 0 ? std::fabs(err) : std::max(err, Real(0));
    });
    for (size_t i = 0; i < n; ++i)
      maxErr = std::max(maxErr, ps.density[i] / ps.restDensity[i] + dt * rate_[i] - 1);
    stats.iterations = it;
    stats.meanError = sum / Real(n);
    stats.maxError = maxErr;
    if (it >= settings_.minIterations && stats.meanError <= settings_.densityTolerance) return stats;
    for (size_t i = 0; i < n; ++i) p[i] += delta_[i];
    applyPressure(ctx, ps, delta_, dt);
  }
  stats.iterations = settings_.maxIterations;
  stats.converged = false;
  return stats;
}

PressureSolveStats DfsphSolver::solveDivergence(const StepContext& ctx, ParticleSet& ps, Real dt) {
  const size_t n = ps.size();
  PressureSolveStats stats;
  if (n == 0) return stats;
  std::vector<Real>& p = ps.divergencePressure;
  applyPressure(ctx, ps, p, dt);
  delta_.resize(n);
  const Real inv = 1 / dt;
  for (int it = 0; it < settings_.maxIterations; ++it) {
    densityRate(ctx, ps);
    const Real sum = blockSum(n, [&](size_t i) {
      // Only where the fluid is (about to be) at rest density: a free surface may expand.
      // Where the fluid is (about to be) at rest density, d theta/dt = 0; elsewhere (a free
      // surface, a splash) it may expand, and only a pressure left from before is undone.
      const bool dense = ps.density[i] / ps.restDensity[i] + dt * rate_[i] >= 1;
      const Real err = dense ? rate_[i] : std::min(rate_[i], Real(0));
      const Real next = diagonal_[i] > 0 ? std::max(Real(0), p[i] + kRelaxation * err * inv / diagonal_[i]) : Real(0);
      delta_[i] = next - p[i];
      return (next > 0 ? std::fabs(err) : std::max(err, Real(0))) * dt;
    });
    stats.iterations = it;
    stats.meanError = sum / Real(n);
    if (it >= settings_.minIterations && stats.meanError <= settings_.divergenceTolerance) return stats;
    for (size_t i = 0; i < n; ++i) p[i] += delta_[i];
    applyPressure(ctx, ps, delta_, dt);
  }
  stats.iterations = settings_.maxIterations;
  stats.converged = false;
  return stats;
}

}  // namespace mf
