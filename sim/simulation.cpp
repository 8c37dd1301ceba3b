#include "simulation.h"

#include "pressure/dfsph.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "parallel_util.h"
#include "scene_file.h"
#include "solids.h"

namespace mf {

namespace {

// splitmix64: small, fast, and the same on every platform; seeded per particle so that
// seeding does not depend on iteration order.
uint64_t splitmix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
Real uniform01(uint64_t x) { return Real(splitmix(x) >> 11) * (1.0 / 9007199254740992.0); }

}  // namespace

BlockLattice blockLattice(const FluidBlockSpec& f, Real s) {
  Vec3 lo, hi;
  f.bounds(lo, hi);
  BlockLattice l;
  for (int a = 0; a < 3; ++a) {
    // Bounded so that a huge block cannot overflow int (the budget refuses such scenes first).
    l.n[a] = int(std::min(1e9, std::max(0.0, std::floor((hi[a] - lo[a]) / s + 1e-6))));
    l.start[a] = lo[a] + 0.5 * ((hi[a] - lo[a]) - (l.n[a] - 1) * s);
  }
  return l;
}

Real latticeKernelSum(const SphKernels& K, Real s) {
  return sumOverRestLattice(K, s, [&](int i, int j, int k) {
    const int r2 = i * i + j * j + k * k;
    return r2 == 0 ? K.selfWeight : K.densityChecked(s * s * Real(r2));
  });
}

Real phaseParticleMass(const PhaseSpec& ph, const SphKernels& kernels, Real spacing) {
  return ph.particleMass > 0 ? ph.particleMass : ph.restDensity / latticeKernelSum(kernels, spacing);
}

ParticleInit newParticleOfPhase(const PhaseSpec& ph, uint16_t phaseIndex, Real mass, const Vec3& x, const Vec3& v,
                                Real temperature) {
  ParticleInit p;
  p.phase = phaseIndex;
  p.position = x;
  p.velocity = v;
  p.restDensity = ph.restDensity;
  p.mass = mass;
  p.viscosity = ph.viscosity;
  p.stiffness = ph.stiffness;
  p.interfaceColour = ph.interfaceColour;
  p.surfaceColour = ph.surfaceColour;
  p.temperature = temperature;
  return p;
}

std::vector<Real> phaseParticleMasses(const Scene& scene) {
  const SphKernels K(scene.solver.particleSpacing * scene.solver.smoothingRatio, scene.solver.kernel,
                     scene.solver.particleSpacing);
  std::vector<Real> m;
  for (const PhaseSpec& ph : scene.phases) m.push_back(phaseParticleMass(ph, K, scene.solver.particleSpacing));
  return m;
}

Real latticeGradientMoment(const SphKernels& K, Real s) {
  const Real volume = 1.0 / latticeKernelSum(K, s);
  return sumOverRestLattice(K, s, [&](int i, int j, int k) {
    const Vec3 xj(i * s, j * s, k * s);  // neighbour; particle i at the origin
    return volume * xj.y * K.pressureGrad(-xj, lengthSquared(xj)).y;
  });
}

Simulation::Simulation(const Scene& scene)
    : scene_(scene), leftDomain_(scene.phases.size(), 0), bornByPhase_(scene.phases.size(), 0) {
  const SolverSettings& st = scene_.solver;
  kernels_ = SphKernels(st.particleSpacing * st.smoothingRatio, st.kernel, st.particleSpacing);
  // Gradient normalisation on the rest lattice: sum_j V_j (x_j - x_i) (x) grad W_ij should be
  // the identity, so that a linear pressure field gives exactly its gradient. At h = 2 spacings
  // the spiky kernel gives 0.947 and Wendland C2 0.950 (settled hydrostatic pressure 5 % high);
  // one constant factor, computed once, fixes that without touching the force's symmetry, and
  // a constant factor keeps a conservative force conservative.
  gradientMoment_ = latticeGradientMoment(kernels_, st.particleSpacing);
  kernels_.scalePressureGradient(1 / gradientMoment_);
  if (st.freeSurfaceCompletion) {
    // The table is for a continuous half-space; the seeding lattice's flat face is what must
    // start at rest density, so the answer is scaled to be exact for its outer layer (at
    // h = 2 spacings the table says 0.155 where the lattice misses 0.128: unscaled, a cube's
    // faces started 2 % compressed, 2e3 Pa against a Laplace pressure of 27, and the drop burst).
    // Tilted faces, edges and corners then read a little below rho0 (0.91 rho0 at a corner):
    // an underestimate, which the clamp turns into no pressure rather than a push.
    surfaceMissing_ = HalfSpaceMissing(kernels_);
    const Real s = st.particleSpacing, V = 1 / latticeKernelSum(kernels_, s);
    const auto layer0 = [&](bool moment) {  // neighbours on or below the outer layer (k <= 0)
      return sumOverRestLattice(kernels_, s, [&](int i, int j, int k) {
        const int r2 = i * i + j * j + k * k;
        if (k > 0) return Real(0);
        const Real w = V * (r2 == 0 ? kernels_.selfWeight : kernels_.densityChecked(s * s * Real(r2)));
        return moment ? w * k * s : w;
      });
    };
    const Real filled = layer0(false), zeta = std::fabs(layer0(true)) / (filled * kernels_.h);
    surfaceMissing_.scale = (1 - filled) / surfaceMissing_.unscaled(zeta);
  }

  for (const PhaseSpec& p : scene_.phases)
    if (p.addedDensity > 0) {
      for (const PhaseSpec& q : scene_.phases) addedDensity_.push_back(q.addedDensity);
      break;
    }

  const Real wallSpacing = st.particleSpacing * st.boundarySpacingRatio;
  const bool implicit = st.pressure == PressureSolverChoice::DFSPH;
  const WallCalibration wall0 = implicit ? calibrateImplicitWall(kernels_, st.particleSpacing, wallSpacing) : WallCalibration{};
  wallOffset_ = implicit ? wall0.offset : wallSampleOffset(kernels_, st.particleSpacing, wallSpacing);
  const PeriodicDomain periodic = scene_.periodic();
  std::vector<Vec3> wall = sampleSolidSurfaces(scene_.solids, wallSpacing, wallOffset_, periodic);
  Vec3 lo = scene_.domainMin;
  for (const Vec3& p : wall) lo = cwiseMin(lo, p);
  gridOrigin_ = lo - Vec3(kernels_.h, kernels_.h, kernels_.h);
  boundary_ = makeBoundarySamples(std::move(wall), kernels_, gridOrigin_, wall0.volumeScale, periodic);
  if (boundary_.size() > 0) boundaryGrid_.build(boundary_.position.data(), boundary_.size(), gridOrigin_, kernels_.h);

  AttributeMask attributes = 0;
  for (const EffectSpec& spec : scene_.effects) {
    const EffectInfo* info = findEffect(spec.name);
    if (!info) throw std::invalid_argument("unknown effect " + spec.name);
    // The implicit solver is the pressure force itself: the explicit one is left out.
    if (implicit && spec.name == "pressure") continue;
    effects_.push_back(info->create(spec, scene_));
  }
  if (implicit) {
    DfsphSettings ds;
    ds.densityTolerance = st.densityTolerance;
    ds.divergenceTolerance = st.divergenceTolerance;
    ds.maxIterations = st.maxPressureIterations;
    ds.conjugateGradient = st.conjugateGradient;
    // The pressure table's hydrostatic reference carries over to the implicit solve (not while
    // gravity ramps in: the reference is the full weight).
    const EffectSpec* pressure = scene_.effect("pressure");
    const EffectSpec* gravity = scene_.effect("gravity");
    if (pressure && gravity && gravity->number("ramp_time") == 0) ds.reference = HydrostaticReference::of(*pressure, scene_);
    dfsph_ = std::make_unique<DfsphSolver>(ds);
    attributes |= bit(Attribute::DivergencePressure);
  }
  // Keep the registry's order, whatever the order in the file (fixed order = same rounding).
  std::stable_sort(effects_.begin(), effects_.end(), [](const auto& a, const auto& b) {
    auto rank = [](const char* n) {
      const auto& reg = effectRegistry();
      for (size_t i = 0; i < reg.size(); ++i)
        if (reg[i].name == n) return i;
      return reg.size();
    };
    return rank(a->name()) < rank(b->name());
  });
  for (const auto& e : effects_) attributes |= e->requiredAttributes();
  ps_.enable(attributes);

  seedFluid();
  if (dfsph_) seedHydrostaticPressure();
  for (const auto& e : effects_) e->prepare(ps_);
  refresh();
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::seedFluid() {
  const Real s = scene_.solver.particleSpacing;
  const Real latticeSum = latticeKernelSum(kernels_, s);
  std::vector<ParticleInit> candidates;
  for (size_t b = 0; b < scene_.fluids.size(); ++b) {
    const FluidBlockSpec& f = scene_.fluids[b];
    const BlockLattice lattice = blockLattice(f, s);
    const int* n = lattice.n;
    Real cumulative = 0;
    std::vector<Real> cdf;
    for (Real w : f.fractions) cdf.push_back(cumulative += w);
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const uint64_t latticeIndex = (uint64_t(b) << 48) ^ (uint64_t(k) << 32) ^ (uint64_t(j) << 16) ^ uint64_t(i);
          const uint64_t rngBase = splitmix(f.seed * 0x100000001b3ULL ^ latticeIndex);
          Vec3 x = lattice.point(i, j, k, s);
          if (f.jitter > 0)
            x += Vec3(uniform01(rngBase + 1) - 0.5, uniform01(rngBase + 2) - 0.5, uniform01(rngBase + 3) - 0.5) *
                 (2 * f.jitter * s);
          if (!f.seeds(x)) continue;
          // A curved wall cuts the lattice anywhere: wall_margin leaves out points that would sit
          // closer to it than the half spacing flat walls keep (they start strongly repelled).
          if (f.insideSolid >= 0 && !insideFluidRegion(scene_.solids[size_t(f.insideSolid)], x, -f.wallMargin * s)) continue;
          size_t pick = 0;
          if (f.phases.size() > 1) {
            const Real u = uniform01(rngBase) * cumulative;
            while (pick + 1 < f.phases.size() && u >= cdf[pick]) ++pick;
          }
          const PhaseSpec& ph = scene_.phases[f.phases[pick]];
          ParticleInit p;
          p.phase = f.phases[pick];
          p.position = x;
          p.velocity = f.velocity;
          p.restDensity = ph.restDensity;
          p.mass = ph.particleMass > 0 ? ph.particleMass : ph.restDensity / latticeSum;
          p.viscosity = ph.viscosity;
          p.stiffness = ph.stiffness;
          p.interfaceColour = ph.interfaceColour;
          p.surfaceColour = ph.surfaceColour;
          p.temperature = f.temperature;
          p.dye = f.dye;
          candidates.push_back(p);
        }
  }
  // Leave out lattice points outside the domain or within half a spacing of a wall sample.
  std::vector<Vec3> cx(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) cx[i] = candidates[i].position;
  std::vector<uint8_t> keep(candidates.size(), 1);
  if (boundary_.size() > 0 && !cx.empty()) {
    CellGrid g;
    g.build(cx.data(), cx.size(), gridOrigin_, kernels_.h);
    NeighborLists nl;
    g.findNeighbors(boundaryGrid_, 0.45 * s, false, nl, scene_.periodic());
    for (size_t i = 0; i < cx.size(); ++i) keep[i] = nl.count(i) == 0;
  }
  ps_.reserve(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Vec3& x = cx[i];
    bool inDomain = true;
    for (int a = 0; a < 3; ++a) inDomain &= x[a] >= scene_.domainMin[a] && x[a] <= scene_.domainMax[a];
    if (keep[i] && inDomain) ps_.append(nextId_++, candidates[i]);
  }
}

StepContext Simulation::context() const {
  return {kernels_,    fluidNeighbors_, boundaryNeighbors_,
          boundary_,   time_,           &fluidGrid_,
          boundary_.size() > 0 ? &boundaryGrid_ : nullptr, gridOrigin_, scene_.solver.particleSpacing,
          scene_.periodic(), addedDensity_.empty() ? nullptr : &addedDensity_};
}

void Simulation::refresh() { searchAndDensity(); }

void Simulation::computePressure() {
  const auto t0 = Clock::now();
  const bool clamp = scene_.solver.clampNegativePressure;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ps_.size(), kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Real p = ps_.stiffness[i] * (ps_.density[i] - ps_.restDensity[i]);  // P = k (rho - rho0)
      ps_.pressure[i] = clamp && p < 0 ? 0 : p;
    }
  });
  times_.density += since(t0);
}

void Simulation::accumulateForces() {
  std::fill(ps_.force.begin(), ps_.force.end(), Vec3{});
  const StepContext ctx = context();
  times_.effect.resize(effects_.size(), 0);
  for (size_t k = 0; k < effects_.size(); ++k) {
    const auto t0 = Clock::now();
    effects_[k]->accumulateForces(ctx, ps_);
    times_.effect[k] += since(t0);
  }
}

Real Simulation::chooseDt() const {
  const SolverSettings& st = scene_.solver;
  const size_t n = ps_.size();
  const Real vmax = std::sqrt(parallelMax(n, [&](size_t i) { return lengthSquared(ps_.velocity[i]); }));
  const Real kmax = parallelMax(n, [&](size_t i) { return ps_.stiffness[i]; });
  const StepContext ctx = context();
  const Real amax = std::sqrt(parallelMax(n, [&](size_t i) {
    const Real m = inertialMass(ctx, ps_, i);
    return lengthSquared(ps_.force[i]) / (m * m);
  }));
  Real dt = st.maxDt;
  dtLimiter_ = "solver.max_dt";
  auto offer = [&](Real candidate, const char* what) {
    if (candidate < dt) dt = candidate, dtLimiter_ = what;
  };
  if (dfsph_) {
    // Implicit pressure: the flow sets the step (CFL on the particle spacing), not sound.
    if (vmax > 0) offer(st.cfl * st.particleSpacing / vmax, "the flow speed (solver.cfl)");
  } else {
    const Real speed = std::sqrt(kmax) + vmax;
    if (speed > 0) offer(st.cfl * kernels_.h / speed, "the sound speed and flow speed (solver.cfl, phase stiffness)");
  }
  if (amax > 0) offer(st.forceFactor * std::sqrt(kernels_.h / amax), "the largest acceleration (solver.force_factor)");
  for (const auto& e : effects_) offer(e->maxTimeStep(ctx, ps_), e->name());
  if (dt < st.minDt) dt = st.minDt, dtLimiter_ = "solver.min_dt";
  return dt;
}

void Simulation::advect(Real dt, const std::vector<Vec3>& x0) {
  const auto t0 = Clock::now();
  std::vector<uint64_t> clampsPerBlock((ps_.size() + kGrain - 1) / kGrain, 0);
  const Real onWallTolerance = 0.1 * scene_.solver.particleSpacing;
  const PeriodicDomain periodic = scene_.periodic();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ps_.size(), kGrain), [&](const tbb::blocked_range<size_t>& r) {
    uint64_t clamps = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Vec3 v = ps_.velocity[i];
      Vec3 x = periodic.wrap(x0[i] + v * dt);
      // A container is never crossed: a particle that was inside (or on the wall, within
      // rounding) and would end outside is put back on the wall. Matters for splashes whose
      // density stays below rest density (no pressure, so no wall force) and violent steps.
      // Above an open top there is no wall: a splash leaves over the rim.
      for (const SolidSpec& s : scene_.solids)
        if (!insideFluidRegion(s, x) && insideFluidRegion(s, x0[i], onWallTolerance) && !aboveOpenTop(s, x0[i]))
          clamps += clampToFluidRegion(s, x, v);
      ps_.velocity[i] = v;
      ps_.position[i] = x;
    }
    clampsPerBlock[r.begin() / kGrain] += clamps;
  });
  uint64_t clamps = 0;
  for (uint64_t c : clampsPerBlock) clamps += c;
  counters_.wallClamps = clampsBeforeStep_ + clamps;
  times_.integrate += since(t0);
}

void Simulation::accelerate(Real dt, const std::vector<Vec3>& v0) {
  const auto t0 = Clock::now();
  const StepContext ctx = context();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ps_.size(), kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) ps_.velocity[i] = v0[i] + ps_.force[i] * (dt / inertialMass(ctx, ps_, i));
  });
  times_.integrate += since(t0);
}

void Simulation::integrate(Real dt, const std::vector<Vec3>& x0, const std::vector<Vec3>& v0) {
  // Symplectic Euler: v(t+dt) = v + dt F/m (eq. 8), then x(t+dt) = x + dt v(t+dt).
  accelerate(dt, v0);
  advect(dt, x0);
}

int64_t Simulation::findInvalidParticle(Real dt, std::string& why, std::string& parameter) const {
  const Real maxMove = scene_.solver.maxMoveRatio * kernels_.h;
  const Real maxErr = scene_.solver.maxDensityError;
  auto rule = [&](size_t i) -> int {
    if (!isFinite(ps_.position[i]) || !isFinite(ps_.velocity[i]) || !std::isfinite(ps_.density[i])) return 1;
    if (length(ps_.velocity[i]) * dt > maxMove) return 2;
    if ((ps_.density[i] - ps_.restDensity[i]) > maxErr * ps_.restDensity[i]) return 3;
    return 0;
  };
  const int64_t first = firstIndexWhere(ps_.size(), [&](size_t i) { return rule(i) != 0; });
  if (first < 0) return -1;
  const size_t i = size_t(first);
  const PhaseSpec& ph = scene_.phases[ps_.phase[i]];
  switch (rule(i)) {
    case 1:
      why = fmt::format("non-finite state (x = ({}, {}, {}), v = ({}, {}, {}), rho = {})", ps_.position[i].x,
                        ps_.position[i].y, ps_.position[i].z, ps_.velocity[i].x, ps_.velocity[i].y,
                        ps_.velocity[i].z, ps_.density[i]);
      parameter = "solver.max_dt or solver.cfl (a NaN that survives smaller steps comes from the inputs: check the scene's values)";
      break;
    case 2:
      why = fmt::format("moved {:.3g} h in one step (|v| = {:.4g} m/s, limit {} h)", length(ps_.velocity[i]) * dt / kernels_.h,
                        length(ps_.velocity[i]), scene_.solver.maxMoveRatio);
      // DFSPH has no stiffness: its step and tolerance are what set the motion per step.
      parameter = dfsph_ ? fmt::format("solver.cfl (now {}) or solver.max_dt (now {})", scene_.solver.cfl, scene_.solver.maxDt)
                         : fmt::format("solver.cfl (now {}) or the stiffness of phase \"{}\" (k = {})", scene_.solver.cfl, ph.name, ph.stiffness);
      break;
    default:
      why = fmt::format("compressed by {:.1f}% (rho = {:.6g}, rho0 = {:.6g}, limit {:.0f}%)",
                        100 * (ps_.density[i] / ps_.restDensity[i] - 1), ps_.density[i], ps_.restDensity[i], 100 * maxErr);
      parameter = dfsph_ ? fmt::format("solver.cfl (now {}) or solver.density_tolerance (now {})", scene_.solver.cfl,
                                       scene_.solver.densityTolerance)
                         : fmt::format("the stiffness of phase \"{}\" (k = {}, too soft for this flow) or solver.cfl", ph.name, ph.stiffness);
  }
  return first;
}

void Simulation::checkInputs() const {
  // The solver never leaves a non-finite state behind (the end-of-step check), so one found
  // here was put in from outside: a corrupt checkpoint or a tool editing the particles.
  const int64_t bad = firstIndexWhere(ps_.size(), [&](size_t i) {
    return !isFinite(ps_.position[i]) || !isFinite(ps_.velocity[i]) || !std::isfinite(ps_.mass[i]) || !(ps_.mass[i] > 0);
  });
  if (bad < 0) return;
  const size_t i = size_t(bad);
  throw NumericalInstability(fmt::format(
      "invalid input before step {} (t = {:.6g} s): particle id {} of phase \"{}\" has x = ({}, {}, {}), v = ({}, {}, {}), "
      "m = {}. The solver never writes such values: the state was modified from outside or read from a corrupt checkpoint.",
      counters_.steps, time_, ps_.id[i], scene_.phases[ps_.phase[i]].name, ps_.position[i].x, ps_.position[i].y,
      ps_.position[i].z, ps_.velocity[i].x, ps_.velocity[i].y, ps_.velocity[i].z, ps_.mass[i]));
}

bool Simulation::leavesDomain(const Vec3& x) const {
  for (int a = 0; a < 3; ++a)
    if (!((scene_.periodicAxes >> a) & 1) && (x[a] < scene_.domainMin[a] || x[a] > scene_.domainMax[a])) return true;
  return false;
}

void Simulation::removeOutOfDomain() {
  const size_t n = ps_.size();
  std::vector<uint8_t> out(n, 0);
  bool any = false;
  for (size_t i = 0; i < n; ++i) {
    const Vec3& x = ps_.position[i];
    if (leavesDomain(x)) out[i] = 1;
    any |= out[i] != 0;
    if (out[i]) ++leftDomain_[ps_.phase[i]];
  }
  if (!any) return;
  counters_.removedOutOfDomain += ps_.removeFlagged(out);
  searchAndDensity();
}

void Simulation::editParticles() {
  // Scenes whose effects never create or remove particles keep the plain domain check.
  bool anyEditor = false;
  for (const auto& e : effects_) anyEditor |= e->editsParticles();
  if (!anyEditor) {
    removeOutOfDomain();
    return;
  }
  const size_t n = ps_.size();
  ParticleEdits edits;
  edits.remove.assign(n, 0);
  const StepContext ctx = context();
  for (size_t k = 0; k < effects_.size(); ++k) {
    if (!effects_[k]->editsParticles()) continue;
    const auto t0 = Clock::now();
    effects_[k]->editParticles(ctx, ps_, edits);
    edits.bornBy.resize(edits.births.size(), uint32_t(k));
    times_.effect[k] += since(t0);
  }
  const auto t0 = Clock::now();
  uint64_t byEffects = 0, outside = 0;
  for (size_t i = 0; i < n; ++i) {
    if (edits.remove[i]) {
      ++byEffects;
      continue;
    }
    const Vec3& x = ps_.position[i];
    if (leavesDomain(x)) edits.remove[i] = 1;
    if (edits.remove[i]) ++outside, ++leftDomain_[ps_.phase[i]];
  }
  if (byEffects + outside > 0) ps_.removeFlagged(edits.remove);
  counters_.removedByEffects += byEffects;
  counters_.removedOutOfDomain += outside;
  // Births in the order the effects gave them; ids from the counter, which only grows.
  ps_.reserve(ps_.size() + edits.births.size());
  for (const ParticleInit& p : edits.births) {
    ps_.append(nextId_++, p);
    ++bornByPhase_[p.phase];
  }
  counters_.born += edits.births.size();
  if (byEffects + outside > 0 || !edits.births.empty()) searchAndDensity();
  times_.edits += since(t0);
}

Real Simulation::step(Real maxDt) {
  const SolverSettings& st = scene_.solver;
  if (counters_.steps > 0 && counters_.steps % uint64_t(st.reorderInterval) == 0) {
    // Memory order follows the grid's Z-order, so neighbours stay close in the caches.
    const std::vector<uint32_t> order = fluidGrid_.sortedIndices();
    ps_.permute(order);
    searchAndDensity();
  }
  checkInputs();
  const Real dt = dfsph_ ? stepDfsph(maxDt) : stepWcsph(maxDt);
  // Non-mechanical state (temperature, dye, rest density) from the rates of the step's start.
  {
    const StepContext ctx = context();
    for (size_t k = 0; k < effects_.size(); ++k) {
      const auto t0 = Clock::now();
      effects_[k]->advance(ctx, ps_, dt);
      times_.effect[k] += since(t0);
    }
  }
  time_ += dt;
  ++counters_.steps;
  counters_.lastDt = dt;
  counters_.maxDensityError = std::max(counters_.maxDensityError, ps_.largestCompression());
  editParticles();
  return dt;
}

void Simulation::snapshotStep() {
  savedPosition_ = ps_.position;
  savedVelocity_ = ps_.velocity;
  clampsBeforeStep_ = counters_.wallClamps;
}

Real Simulation::stepWcsph(Real maxDt) {
  computePressure();
  accumulateForces();
  Real dt = std::min(chooseDt(), maxDt);
  snapshotStep();
  for (int attempt = 0;; ++attempt) {
    integrate(dt, savedPosition_, savedVelocity_);
    searchAndDensity();
    std::string why, parameter;
    const int64_t bad = findInvalidParticle(dt, why, parameter);
    if (bad < 0) return dt;
    retryOrStop(attempt, dt, bad, why, parameter);
    dt *= 0.5;
  }
}

void Simulation::retryOrStop(int attempt, Real dt, int64_t bad, const std::string& why, const std::string& parameter) {
  const uint64_t badId = bad >= 0 ? ps_.id[size_t(bad)] : 0;
  const std::string phaseName = bad >= 0 ? scene_.phases[ps_.phase[size_t(bad)]].name : "";
  ps_.position = savedPosition_;
  ps_.velocity = savedVelocity_;
  searchAndDensity();
  if (attempt >= scene_.solver.maxRetries || dt * 0.5 < scene_.solver.minDt) {
    const std::string who = bad >= 0 ? fmt::format("particle id {} of phase \"{}\" {}", badId, phaseName, why) : why;
    throw NumericalInstability(fmt::format(
        "simulation unstable at step {} (t = {:.6g} s, dt = {:.3g} s after {} retries): {}. Parameter most likely at fault: {}.",
        counters_.steps, time_, dt, attempt, who, parameter));
  }
  lastRetry_ = fmt::format("step {}, t = {:.6g} s, dt = {:.3g} s: {}{}", counters_.steps, time_, dt,
                           bad >= 0 ? fmt::format("particle id {} of phase \"{}\" ", badId, phaseName) : "", why);
  ++counters_.retries;
}

void Simulation::advanceTo(Real t, const std::function<void(const Simulation&)>& afterStep) {
  while (time_ < t) {
    const Real remaining = t - time_;
    if (remaining <= 1e-12 * std::max(Real(1), t)) break;
    // Even out the last sub-steps so that none is a sliver. DFSPH does this against its flow
    // step, which it knows only inside the step (stepDfsph).
    step(dfsph_ ? remaining : evenStep(remaining, scene_.solver.maxDt));
    if (afterStep) afterStep(*this);
  }
  // A frame's state is what a checkpoint restores: neighbour lists and density from a search at
  // the positions reached, as loadCheckpoint rebuilds them, so that a resumed run has the same bits.
  if (listsStale_) searchAndDensity();
  time_ = t;
}

}  // namespace mf
