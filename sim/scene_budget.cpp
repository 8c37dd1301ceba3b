#include "scene_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels.h"
#include "scene_file.h"
#include "simulation.h"
#include "solids.h"

namespace mf {

namespace {

// Bytes per item, measured on this project's runs (sim_bench: 654 MiB peak at 986 078 dam-break
// particles, about 700 B each with neighbour lists; surface_bench: 128 MiB for 2.2 M band voxels)
// and rounded up so that the estimate is an upper bound.
constexpr double kBytesPerParticle = 1024;
constexpr double kBytesPerBoundarySample = 256;
constexpr double kBytesPerVoxel = 64;
constexpr double kBytesPerPixel = 64;   // accumulation, EXR and PNG copies, AOV-free
constexpr double kBaseBytes = 64e6;     // program, libraries, TBB arenas
// Lattice points the exact seeding count below visits at most; beyond this the count is only
// estimated (such scenes are refused by their memory estimate anyway).
constexpr double kExactCountLimit = 2e7;

/// Of n lattice points start + i s on one axis, how many lie in the domain's [dlo, dhi].
double pointsInRange(int n, Real start, Real s, Real dlo, Real dhi) {
  if (n <= 0) return 0;
  const double first = std::max(0.0, std::ceil((dlo - start) / s - 1e-9));
  const double last = std::min(double(n - 1), std::floor((dhi - start) / s + 1e-9));
  return std::max(0.0, last - first + 1);
}

/// Top of a solid's fluid region (the rim of an open container), or +inf if it has none.
Real solidTop(const SolidSpec& s) {
  switch (s.shape) {
    case SolidSpec::Shape::Box: return s.max.y;
    case SolidSpec::Shape::Cylinder: return s.base.y + s.height;
    case SolidSpec::Shape::Revolution: return s.base.y + s.profile.back().first;
  }
  return INFINITY;
}

double solidArea(const SolidSpec& s) {
  switch (s.shape) {
    case SolidSpec::Shape::Box: {
      const Vec3 d = s.max - s.min;
      return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
    case SolidSpec::Shape::Cylinder: return 2 * kPi * s.radius * s.height + 2 * kPi * s.radius * s.radius;
    case SolidSpec::Shape::Revolution: {
      double a = kPi * (s.profile.front().second * s.profile.front().second + s.profile.back().second * s.profile.back().second);
      for (size_t i = 1; i < s.profile.size(); ++i) {
        const Real dy = s.profile[i].first - s.profile[i - 1].first, r0 = s.profile[i - 1].second, r1 = s.profile[i].second;
        a += kPi * (r0 + r1) * std::sqrt(dy * dy + (r1 - r0) * (r1 - r0));
      }
      return a;
    }
  }
  return 0;
}

struct BlockCount {
  double lattice = 0;  // lattice points inside the domain
  double seeded = 0;   // of those, the ones the block keeps (sphere, container, wall margin)
};

BlockCount countBlock(const Scene& sc, const FluidBlockSpec& f) {
  const Real s = sc.solver.particleSpacing;
  const BlockLattice l = blockLattice(f, s);
  BlockCount c;
  c.lattice = 1;
  for (int a = 0; a < 3; ++a) c.lattice *= pointsInRange(l.n[a], l.start[a], s, sc.domainMin[a], sc.domainMax[a]);
  if (c.lattice == 0 || double(l.n[0]) * l.n[1] * l.n[2] > kExactCountLimit) {
    // The region's share of its bounding box (subtracted regions not taken off: an upper bound).
    const Real share = f.shape == FluidBlockSpec::Shape::Box ? 1 : f.shape == FluidBlockSpec::Shape::Cylinder ? kPi / 4 : kPi / 6;
    c.seeded = c.lattice * share;
    return c;
  }
  // The seeding's own lattice and tests (Simulation::seedFluid), counted without storing a point
  // (jitter aside).
  const SolidSpec* solid = f.insideSolid >= 0 ? &sc.solids[size_t(f.insideSolid)] : nullptr;
  for (int k = 0; k < l.n[2]; ++k)
    for (int j = 0; j < l.n[1]; ++j)
      for (int i = 0; i < l.n[0]; ++i) {
        const Vec3 x = l.point(i, j, k, s);
        bool inDomain = true;
        for (int a = 0; a < 3; ++a) inDomain &= x[a] >= sc.domainMin[a] && x[a] <= sc.domainMax[a];
        if (!inDomain) continue;
        if (!f.seeds(x)) continue;
        if (solid && !insideFluidRegion(*solid, x, -f.wallMargin * s)) continue;
        c.seeded += 1;
      }
  return c;
}

/// Particles an emitter's nozzles can add over the scene: rate x open time, the rate of a
/// nozzle at rest density being its cross-section / s^2 layers per spacing travelled.
double emittedParticles(const Scene& sc) {
  const EffectSpec* e = sc.effect("emitter");
  if (!e) return 0;
  const Real s = sc.solver.particleSpacing;
  double total = 0;
  for (const char* kind : {"disc", "box"}) {
    if (!e->lists.count(kind)) continue;
    for (const ParamValues& v : e->lists.at(kind)) {
      const Vec3 vel = v.vector("velocity");
      double rate = v.number("rate");
      if (rate == 0) {
        double area = 0;
        if (std::string(kind) == "disc") {
          area = kPi * v.number("radius") * v.number("radius");
        } else {
          const Vec3 d = v.vector("max") - v.vector("min");
          area = std::max({d.x * d.y, d.y * d.z, d.z * d.x});
        }
        rate = area / (s * s) * length(vel) / s;
      }
      double open = std::max(0.0, std::min<double>(v.number("end"), sc.endTime) - v.number("start"));
      // With sinks, emitted fluid that crosses the domain is removed: at most one crossing's
      // worth is alive at once.
      if (e->lists.count("sink") && !e->lists.at("sink").empty() && length(vel) > 0)
        open = std::min(open, length(sc.domainMax - sc.domainMin) / length(vel));
      total += rate * open;
    }
  }
  return total;
}

struct TimeStepLimit {
  Real dt = INFINITY;
  std::string what, key;
  void offer(Real candidate, std::string w, std::string k) {
    if (candidate < dt) dt = candidate, what = std::move(w), key = std::move(k);
  }
};

/// dt at rest, from the limits the step loop applies (Simulation::chooseDt and the effects'
/// maxTimeStep) evaluated on a fluid at rest on the seeding lattice.
TimeStepLimit restTimeStep(const Scene& sc) {
  TimeStepLimit t;
  const Real s = sc.solver.particleSpacing, h = sc.solver.smoothingRatio * s;
  t.offer(sc.solver.maxDt, "the largest step allowed", "solver.max_dt");
  if (sc.solver.pressure == PressureSolverChoice::DFSPH) {
    // The flow sets DFSPH's step (cfl spacing / v_max). A fluid seeded at rest still falls: take
    // the speed of a fall through its own height, sqrt(2 g H), or the seeded speed if faster.
    Vec3 gv;
    if (const EffectSpec* e = sc.effect("gravity")) gv = e->vector("acceleration");
    const Real g = length(gv);
    const Vec3 up = g > 0 ? gv * (-1 / g) : Vec3(0, 1, 0);
    Real lowest = INFINITY, highest = -INFINITY, seeded = 0;
    for (const FluidBlockSpec& b : sc.fluids) {
      Vec3 lo, hi;
      b.bounds(lo, hi);
      // The block's bounding box along up: its lowest and highest corner.
      Real below = 0, above = 0;
      for (int k = 0; k < 3; ++k) below += std::min(up[k] * lo[k], up[k] * hi[k]), above += std::max(up[k] * lo[k], up[k] * hi[k]);
      lowest = std::min(lowest, below), highest = std::max(highest, above);
      seeded = std::max(seeded, length(b.velocity));
    }
    const Real speed = std::max(seeded, highest > lowest ? std::sqrt(2 * g * (highest - lowest)) : Real(0));
    if (speed > 0) t.offer(sc.solver.cfl * s / speed, "the flow speed (a fall through the fluid's height, or its seeded speed)", "solver.cfl");
  }
  for (size_t p = 0; p < sc.phases.size(); ++p) {
    const PhaseSpec& ph = sc.phases[p];
    if (sc.solver.pressure == PressureSolverChoice::WCSPH && ph.stiffness > 0)
      t.offer(sc.solver.cfl * h / std::sqrt(ph.stiffness), fmt::format("the sound speed of phase \"{}\"", ph.name),
              fmt::format("phase[{}].stiffness", p));
    // With DFSPH the viscosity is implicit (effects/implicit_viscosity.h) and sets no step.
    if (const EffectSpec* v = sc.effect("viscosity"); v && ph.viscosity > 0 && sc.solver.pressure == PressureSolverChoice::WCSPH)
      t.offer(v->number("stability_factor") * h * h * ph.restDensity / ph.viscosity,
              fmt::format("the explicit viscosity of phase \"{}\"", ph.name), fmt::format("phase[{}].viscosity", p));
  }
  // Diffusion: dt <= factor / row sum, the row sum on the rest lattice being 2 alpha times the
  // ratio of the Laplacian's zeroth and second moments (the effect's own normalisation).
  const SphKernels K(h, sc.solver.kernel, s);
  const Real lap0 = sumOverRestLattice(K, s, [&](int a, int b, int c) {
    const Real r = s * std::sqrt(Real(a * a + b * b + c * c));
    return r > 0 ? K.viscosityLaplacian(r) : 0;
  });
  const Real lap2 = sumOverRestLattice(K, s, [&](int a, int b, int c) {
    const Real r = s * std::sqrt(Real(a * a + b * b + c * c));
    return (a * s) * (a * s) * K.viscosityLaplacian(r);
  });
  for (const auto& [effect, key] : {std::pair<const char*, const char*>{"heat_diffusion", "thermal_diffusivity"},
                                    std::pair<const char*, const char*>{"dye_diffusion", "dye_diffusivity"}}) {
    const EffectSpec* e = sc.effect(effect);
    if (!e) continue;
    Real sourceRate = 0;  // a particle inside a source box exchanges at its rate on top
    for (const ParamValues& v : e->list("source")) sourceRate = std::max(sourceRate, v.number("rate"));
    if (sourceRate > 0) t.offer(e->number("stability_factor") / sourceRate, std::string(effect) + " source", std::string("effects.") + effect + ".source.rate");
    for (size_t p = 0; p < sc.phases.size(); ++p) {
      const Real alpha = std::string(key) == "thermal_diffusivity" ? sc.phases[p].thermalDiffusivity : sc.phases[p].dyeDiffusivity;
      if (alpha > 0 && lap2 > 0)
        t.offer(e->number("stability_factor") / (2 * alpha * lap0 / lap2 + sourceRate), fmt::format("{} of phase \"{}\"", effect, sc.phases[p].name),
                fmt::format("phase[{}].{}", p, key));
    }
  }
  // Capillary limit (Brackbill): dt <= factor sqrt(rho_min dx^3 / (2 pi sigma_max)).
  Real rhoMin = INFINITY;
  for (const PhaseSpec& ph : sc.phases) rhoMin = std::min(rhoMin, ph.restDensity);
  auto capillary = [&](const EffectSpec& e, Real sigma, const std::string& key) {
    if (sigma > 0) t.offer(e.number("time_step_factor") * std::sqrt(rhoMin * s * s * s / (2 * kPi * sigma)), e.name, key);
  };
  if (const EffectSpec* e = sc.effect("interface_tension")) {
    capillary(*e, e->number("sigma"), "effects.interface_tension.sigma");
    for (const ParamValues& pair : e->list("pair")) capillary(*e, pair.number("sigma"), "effects.interface_tension.pair.sigma");
  }
  if (const EffectSpec* e = sc.effect("surface_tension"))
    for (size_t p = 0; p < sc.phases.size(); ++p) capillary(*e, sc.phases[p].surfaceTension, fmt::format("phase[{}].surface_tension", p));
  if (const EffectSpec* e = sc.effect("damping")) t.offer(0.5 / std::max(1e-300, e->number("rate")), "damping", "effects.damping.rate");
  t.offer(std::max<Real>(t.dt, sc.solver.minDt), t.what, t.key);
  return t;
}

}  // namespace

double defaultMemoryLimit() {
  double limit = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
  struct rlimit rl {};
  if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) limit = std::min(limit, double(rl.rlim_cur));
  return 0.8 * limit;
}

namespace {
/// The estimate from the blocks' counts (one countBlock per block, in scene order).
SceneBudget estimateFromCounts(const Scene& sc, const std::vector<BlockCount>& counts, const LaterStageSizes& later) {
  SceneBudget b;
  for (const BlockCount& c : counts) b.particles += c.seeded;
  b.emitted = emittedParticles(sc);
  const Real bs = sc.solver.boundarySpacingRatio * sc.solver.particleSpacing;
  for (const SolidSpec& s : sc.solids) b.boundarySamples += solidArea(s) / (bs * bs);
  // The surfacing band: about 6 voxels thick over the fluid's surface, at most the surface of
  // every particle's own sphere (spray), in voxels of voxel_ratio spacings.
  const double peak = b.particles + b.emitted;
  const double vr = later.voxelRatio;
  b.surfaceVoxels = peak * 6.0 * std::pow(1.0 / vr, 2) * 4;
  const double pixels = later.width * later.height;
  const double sim = peak * kBytesPerParticle + b.boundarySamples * kBytesPerBoundarySample;
  const double surface = b.surfaceVoxels * kBytesPerVoxel + peak * 64;
  const double render = pixels * kBytesPerPixel + b.surfaceVoxels * 48;  // meshes from the level sets
  b.memoryBytes = kBaseBytes + std::max({sim, surface, render});
  const TimeStepLimit t = restTimeStep(sc);
  b.restTimeStep = t.dt;
  b.timeStepLimiter = t.what + " (" + t.key + ")";
  b.stepsPerFrame = sc.frameRate > 0 ? 1.0 / (sc.frameRate * t.dt) : 0;
  return b;
}

std::vector<BlockCount> countBlocks(const Scene& sc) {
  std::vector<BlockCount> counts;
  for (const FluidBlockSpec& f : sc.fluids) counts.push_back(countBlock(sc, f));
  return counts;
}
}  // namespace

SceneBudget estimateSceneBudget(const Scene& sc, const LaterStageSizes& later) { return estimateFromCounts(sc, countBlocks(sc), later); }

SceneBudget checkSceneBudget(const Scene& sc, const BudgetLimits& limits, const LaterStageSizes& later) {
  std::vector<SceneProblem> problems;
  auto problem = [&](const std::string& key, const std::string& message) {
    problems.push_back({sc.sourceFile, sc.lineOf(key), key, message});
  };
  const Real s = sc.solver.particleSpacing;
  // Fluid blocks: each must seed particles, and one inside an open container must stay below its
  // rim (above it the container is open, so the points would be seeded outside the glass).
  const std::vector<BlockCount> counts = countBlocks(sc);
  for (size_t k = 0; k < sc.fluids.size(); ++k) {
    const FluidBlockSpec& f = sc.fluids[k];
    const std::string key = fmt::format("fluid[{}]", k);
    const std::string shapeKey = key + (f.shape == FluidBlockSpec::Shape::Box ? ".max" : ".radius");
    const BlockCount& c = counts[k];
    Vec3 lo, hi;
    f.bounds(lo, hi);
    const Real top = hi.y;
    if (f.insideSolid >= 0) {
      const SolidSpec& solid = sc.solids[size_t(f.insideSolid)];
      if (solid.openTop && top > solidTop(solid) + 1e-9)
        problem(f.shape == FluidBlockSpec::Shape::Box ? key + ".max" : key + ".centre",
                fmt::format("the block reaches y = {:g} m, above the rim of \"{}\" at y = {:g} m; it would seed fluid outside it",
                            top, solid.name, solidTop(solid)));
    }
    if (c.seeded > 0) continue;
    const BlockLattice l = blockLattice(f, s);
    const bool smaller = l.n[0] == 0 || l.n[1] == 0 || l.n[2] == 0;  // no lattice point fits an axis
    if (smaller)
      problem(shapeKey, fmt::format("the block is smaller than one particle spacing ({:g} m) and seeds no particle", s));
    else if (c.lattice == 0)
      problem(key + (f.shape == FluidBlockSpec::Shape::Box ? ".min" : f.shape == FluidBlockSpec::Shape::Cylinder ? ".base" : ".centre"),
              "the block lies outside the domain (scene.domain_min .. domain_max) and seeds no particle");
    else if (f.insideSolid >= 0)
      problem(key + ".wall_margin", fmt::format("no lattice point of the block is inside \"{}\" (at wall_margin {:g} spacings): it seeds no particle",
                                                sc.solids[size_t(f.insideSolid)].name, f.wallMargin));
    else
      problem(shapeKey, "the block seeds no particle");
  }
  const SceneBudget b = estimateFromCounts(sc, counts, later);
  const double limit = limits.maxMemoryBytes > 0 ? limits.maxMemoryBytes : defaultMemoryLimit();
  auto mib = [](double bytes) { return bytes / (1024.0 * 1024.0); };
  if (b.memoryBytes > limit) {
    std::string key = "solver.particle_spacing", what = fmt::format("{:.3g} particles", b.particles + b.emitted);
    if (b.boundarySamples * kBytesPerBoundarySample > (b.particles + b.emitted) * kBytesPerParticle) {
      size_t largest = 0;
      for (size_t j = 1; j < sc.solids.size(); ++j)
        if (solidArea(sc.solids[j]) > solidArea(sc.solids[largest])) largest = j;
      key = sc.solids.empty() ? "solid" : fmt::format("solid[{}]", largest);
      what = fmt::format("{:.3g} wall samples of {} solid(s)", b.boundarySamples, sc.solids.size());
    } else if (b.emitted > b.particles) {
      key = "effects.emitter";
      what = fmt::format("{:.3g} emitted particles", b.emitted);
    } else if (later.width * later.height * kBytesPerPixel > b.memoryBytes / 2) {
      key = "render.width";
      what = fmt::format("{}x{} pixels", later.width, later.height);
    }
    problem(key, fmt::format("the scene needs an estimated {:.0f} MiB ({}), over the {:.0f} MiB allowed ({}); use a coarser "
                             "particle_spacing, smaller solids or fewer pixels",
                             mib(b.memoryBytes), what, mib(limit), limits.maxMemoryBytes > 0 ? "--max-memory" : "80 % of this machine's memory"));
  }
  if (limits.maxStepsPerFrame > 0 && b.stepsPerFrame > limits.maxStepsPerFrame && !limits.force) {
    const size_t open = b.timeStepLimiter.rfind('('), close = b.timeStepLimiter.rfind(')');
    const std::string key = open != std::string::npos ? b.timeStepLimiter.substr(open + 1, close - open - 1) : "solver.cfl";
    problem(key, fmt::format("the time step at rest is {:.3g} s, set by {}: {:.3g} steps per frame, over the bound of {:.0f} "
                             "(--max-steps-per-frame); change this key, or pass --force to run anyway",
                             b.restTimeStep, b.timeStepLimiter, b.stepsPerFrame, limits.maxStepsPerFrame));
  }
  if (!problems.empty()) throw SceneError(problems);
  return b;
}

}  // namespace mf
