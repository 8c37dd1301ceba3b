// Simulation's neighbour search and density pass: the lists, the density (sum_j m_j W_ij, or
// the number density, with the walls' Akinci volumes and the free-surface completion) and, on
// DFSPH, the solver's diagonal at the current positions.
#include <tbb/parallel_for.h>

#include <chrono>

#include "parallel_util.h"
#include "pressure/dfsph.h"
#include "simulation.h"

namespace mf {

void Simulation::searchAndDensity(bool search) {
  const auto t0 = Clock::now();
  const size_t n = ps_.size();
  const PeriodicDomain periodic = scene_.periodic();
  listsStale_ = !search;
  if (search) {
    fluidGrid_.build(ps_.position.data(), n, gridOrigin_, kernels_.h);
    fluidGrid_.findNeighbors(fluidGrid_, kernels_.h, true, fluidNeighbors_, periodic);
    if (boundary_.size() > 0) {
      fluidGrid_.findNeighbors(boundaryGrid_, kernels_.h, false, boundaryNeighbors_, periodic);
    } else {
      boundaryNeighbors_.offsets.assign(n + 1, 0);
      boundaryNeighbors_.indices.clear();
    }
  }
  const auto t1 = Clock::now();
  times_.neighborSearch += std::chrono::duration<double>(t1 - t0).count();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) densityOf(i, periodic);
  });
  if (dfsph_) dfsph_->computeDiagonal(context(), ps_);
  times_.density += since(t1);
}

void Simulation::densityNear(const std::vector<uint32_t>& moved) {
  const auto t0 = Clock::now();
  listsStale_ = true;
  // The particles whose density the move changed: the moved ones and their neighbours, in
  // index order (the lists are symmetric, so nobody else has a moved neighbour).
  const size_t n = ps_.size();
  near_.assign(n, 0);
  for (uint32_t i : moved) {
    near_[i] = 1;
    for (uint64_t k = fluidNeighbors_.begin(i), e = fluidNeighbors_.end(i); k < e; ++k) near_[fluidNeighbors_.indices[k]] = 1;
  }
  nearList_.clear();
  for (size_t i = 0; i < n; ++i)
    if (near_[i]) nearList_.push_back(uint32_t(i));
  const PeriodicDomain periodic = scene_.periodic();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nearList_.size(), kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t q = r.begin(); q != r.end(); ++q) densityOf(nearList_[q], periodic);
  });
  if (dfsph_) dfsph_->computeDiagonal(context(), ps_, &nearList_);
  times_.density += since(t0);
}

void Simulation::densityOf(size_t i, const PeriodicDomain& periodic) {
  const bool numberDensity = scene_.solver.density == DensityFormulation::Number;
  const bool complete = scene_.solver.freeSurfaceCompletion;
  const SphKernels& K = kernels_;
  const Real w0 = K.selfWeight;
  const Vec3 xi = ps_.position[i];
  Real fluidSum = 0;  // sum_j m_j W_ij, or sum_j W_ij for number density
  Real filled = 0;    // sum_j V0_j W_ij (rest volumes V0 = m / rho0; walls as fluid)
  Vec3 moment;        // sum_j V0_j (x_j - x_i) W_ij
  for (uint64_t k = fluidNeighbors_.begin(i), e = fluidNeighbors_.end(i); k < e; ++k) {
    const uint32_t j = fluidNeighbors_.indices[k];
    const Vec3 rji = periodic.separation(ps_.position[j], xi);
    const Real w = K.densityChecked(lengthSquared(rji));
    fluidSum += numberDensity ? w : ps_.mass[j] * w;
    if (complete) {
      const Real vw = ps_.mass[j] / ps_.restDensity[j] * w;
      filled += vw;
      moment += rji * vw;
    }
  }
  Real wallSum = 0;  // sum_b V_b W_ib (Akinci 2012): the wall counts as rest-density fluid
  for (uint64_t k = boundaryNeighbors_.begin(i), e = boundaryNeighbors_.end(i); k < e; ++k) {
    const uint32_t b = boundaryNeighbors_.indices[k];
    const Vec3 rbi = periodic.separation(boundary_.position[b], xi);
    const Real vw = boundary_.volume[b] * K.densityChecked(lengthSquared(rbi));
    wallSum += vw;
    if (complete) moment += rbi * vw;
  }
  const Real mi = ps_.mass[i], rho0 = ps_.restDensity[i];
  // Free-surface completion: the part of the kernel a plane surface cuts off, counted as
  // rest-density fluid (as the walls are). Without it the outer layer reads 13-27 % below
  // rho0 on the lattice, has no pressure (clamped) and packs under any inward force.
  Real missing = 0;
  if (complete) {
    filled += wallSum + mi / rho0 * w0;
    missing = surfaceMissing_(length(moment) / (filled * K.h));
  }
  if (numberDensity) {
    const Real delta = fluidSum + w0 + (wallSum + missing) * rho0 / mi;
    ps_.density[i] = mi * delta;
    ps_.volume[i] = 1.0 / delta;
  } else {
    ps_.density[i] = fluidSum + mi * w0 + rho0 * (wallSum + missing);
    ps_.volume[i] = mi / ps_.density[i];
  }
}

}  // namespace mf
