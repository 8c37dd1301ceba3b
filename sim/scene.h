// A scene as plain values: what the scene file says to the simulation, validated, with units in SI.
// Parsing and error reporting live in scene_file.h; nothing here knows about TOML.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "kernels.h"
#include "periodic.h"
#include "vec3.h"

namespace mf {

/// One fluid (phase) of the scene: the per-particle parameters of Mueller et al. 2005, Table 1.
struct PhaseSpec {
  std::string name;
  Real restDensity = 1000;   // rho0, kg/m^3
  Real stiffness = 1000;     // k in P = k (rho - rho0), m^2/s^2 (speed of sound c = sqrt(k))
  Real viscosity = 0;        // mu, Pa s, mixed pairwise as (mu_i + mu_j) / 2 (eq. 9)
  Real particleMass = 0;     // kg; 0: chosen so that a particle on the seeding lattice has rho0
  // kg/m^3 the particle's inertia carries beyond its rest density: a bubble moves as if it carried
  // about half its volume of the liquid around it (its added mass), while its weight and volume
  // keep rest_density. 0 for a liquid.
  Real addedDensity = 0;
  // Material constants read by the effects that use them (ignored, and reported by the scene
  // reader, when that effect is not enabled).
  Real interfaceColour = 0;       // c_i of this fluid (interface_tension); e.g. water -0.5, oil +0.5
  Real surfaceColour = 1;         // c_s: 1 liquid, 0 gas (surface_tension)
  Real surfaceTension = 0;        // sigma_s, N/m (surface_tension)
  Real thermalDiffusivity = 0;    // alpha in dT/dt = alpha lap T, m^2/s (heat_diffusion)
  Real dyeDiffusivity = 0;        // m^2/s (dye_diffusion)
  Real thermalExpansion = 0;      // beta, 1/K: rho0(T) = rho0 / (1 + beta (T - T_ref)) (thermal_expansion)
  Real referenceTemperature = 20; // T_ref, deg C, where rest_density holds
};

/// A container or obstacle, sampled as boundary particles (Akinci et al. 2012).
struct SolidSpec {
  enum class Shape { Box, Cylinder, Revolution };
  std::string name;
  Shape shape = Shape::Box;
  // Box: fluid inside [min, max]; `openTop` leaves out the +y face.
  Vec3 min, max;
  bool openTop = false;
  // Cylinder (a glass): axis +y from `base` (centre of the bottom), fluid inside.
  // Revolution (a lamp vessel): closed surface with radius profile r(y) about the +y axis
  // through `base`; profile points are (height above base, radius), heights increasing.
  Vec3 base;
  Real radius = 0, height = 0;
  std::vector<std::pair<Real, Real>> profile;
};

/// A region of space: a box, a sphere, an ellipsoid or a cylinder. Fluid blocks fill one, and
/// leave out the regions they subtract.
struct FluidRegion {
  enum class Shape { Box, Sphere, Ellipsoid, Cylinder };
  Shape shape = Shape::Box;
  Vec3 min, max;             // box
  Vec3 centre;               // sphere, ellipsoid
  Real radius = 0;           // sphere, cylinder
  Vec3 radii;                // ellipsoid: semi-axes along x, y, z
  Vec3 base;                 // cylinder: centre of its bottom face
  Real height = 0;           // cylinder: length along `axis`
  int axis = 1;              // cylinder: 0 x, 1 y, 2 z

  bool contains(const Vec3& x) const {
    switch (shape) {
      case Shape::Box: return x.x >= min.x && x.x <= max.x && x.y >= min.y && x.y <= max.y && x.z >= min.z && x.z <= max.z;
      case Shape::Sphere: return lengthSquared(x - centre) <= radius * radius;
      case Shape::Ellipsoid: {
        const Vec3 d = x - centre;
        return d.x * d.x / (radii.x * radii.x) + d.y * d.y / (radii.y * radii.y) + d.z * d.z / (radii.z * radii.z) <= 1;
      }
      case Shape::Cylinder: {
        const Vec3 d = x - base;
        const Real along = d[axis], across2 = lengthSquared(d) - along * along;
        return along >= 0 && along <= height && across2 <= radius * radius;
      }
    }
    return false;
  }
  /// The axis-aligned box around the region.
  void bounds(Vec3& lo, Vec3& hi) const {
    switch (shape) {
      case Shape::Box: lo = min, hi = max; return;
      case Shape::Sphere: lo = centre - Vec3(radius, radius, radius), hi = centre + Vec3(radius, radius, radius); return;
      case Shape::Ellipsoid: lo = centre - radii, hi = centre + radii; return;
      case Shape::Cylinder: {
        Vec3 r(radius, radius, radius), top = base;
        r[axis] = 0;
        top[axis] += height;
        lo = cwiseMin(base, top) - r, hi = cwiseMax(base, top) + r;
        return;
      }
    }
  }
};

/// Initial fluid: a region of particles on a cubic lattice, less the regions in `subtract`.
struct FluidBlockSpec : FluidRegion {
  std::vector<FluidRegion> subtract;
  /// A lattice point is seeded when it lies in the block (a box takes its whole lattice,
  /// jitter included) and in no subtracted region.
  bool seeds(const Vec3& x) const {
    if (shape != Shape::Box && !contains(x)) return false;
    for (const FluidRegion& r : subtract)
      if (r.contains(x)) return false;
    return true;
  }
  Vec3 velocity;             // initial velocity, m/s
  // One phase, or a random mix: phases[k] drawn with probability fractions[k] (seeded).
  std::vector<uint16_t> phases;
  std::vector<Real> fractions;
  uint64_t seed = 1;
  Real jitter = 0;           // random displacement, fraction of the particle spacing
  Real temperature = 20;     // initial temperature, deg C (allocated only if an effect uses it)
  Real dye = 0;              // initial dye concentration (dye_diffusion)
  int insideSolid = -1;      // if >= 0: only lattice points inside this container are seeded
  // With insideSolid: ... and at least this many spacings inside its surface. Flat walls keep
  // the lattice's first layer half a spacing off (the walls are calibrated for it); a curved wall
  // cuts the lattice anywhere, and a point closer than that starts compressed against it (the
  // lamp's tapered vessel: 81 % at t = 0 without a margin). 0.05 under half, so that a layer
  // exactly half a spacing off a flat wall is kept.
  Real wallMargin = 0.45;
};

enum class DensityFormulation {
  Mass,    // rho_i = sum_j m_j W_ij (Mueller et al. 2005, eq. 1)
  Number,  // rho_i = m_i sum_j W_ij (Solenthaler & Pajarola 2008): sharp at density jumps
};

/// The error for a WCSPH-only key in a scene that names no solver (and so runs on DFSPH).
inline constexpr const char* kWcsphKeyUnnamed =
    "is read only by the weakly compressible solver, and the scene names no solver.pressure (the default is "
    "\"dfsph\"): set solver.pressure = \"wcsph\" to keep the state equation, or remove it";

enum class PressureSolverChoice {
  WCSPH,  // state equation P = k (rho - rho0) and the pressure effect's force (Mueller et al. 2005)
  DFSPH,  // implicit, divergence-free and constant-density solves (sim/pressure/dfsph.h)
};

struct SolverSettings {
  PressureSolverChoice pressure = PressureSolverChoice::DFSPH;
  bool pressureNamed = false;  // the scene (or an override) names solver.pressure: WCSPH-only keys are then its choice
  // DFSPH: stop at this mean relative density error, and mean divergence error per step.
  Real densityTolerance = 5e-4, divergenceTolerance = 1e-3;
  int maxPressureIterations = 100;
  // DFSPH: a step that leaves a particle compressed by more than this (relative) repeats the
  // constant-density solve at the positions it reached, up to three times.
  Real maxCompression = 0.01;
  // DFSPH's linear iteration: conjugate gradients on the active set, or projected Jacobi.
  bool conjugateGradient = true;
  Real particleSpacing = 0.01;      // m, lattice spacing of seeded fluid
  Real smoothingRatio = 2.0;        // h / spacing; 2 gives about 33 neighbours
  DensityFormulation density = DensityFormulation::Mass;
  KernelChoice kernel = KernelChoice::WendlandC2;  // density and pressure kernels (kernels.h)
  bool clampNegativePressure = true;  // free surfaces: no tensile pressure
  // Free-surface density completion: a particle's density sum gets rho0 times the part of its
  // kernel that a plane free surface would cut off (HalfSpaceMissing, kernels.h), so that the
  // surface layer is at rest density on the lattice and resists packing (see simulation.cpp).
  bool freeSurfaceCompletion = false;
  Real cfl = 0.4;                   // WCSPH: dt <= cfl h / (c_max + v_max); DFSPH: dt <= cfl spacing / v_max
  Real forceFactor = 0.25;          // dt <= forceFactor sqrt(h / a_max)
  Real maxDt = 1e-3, minDt = 1e-8;  // s
  Real boundarySpacingRatio = 0.5;  // boundary sample spacing / particle spacing
  int reorderInterval = 10;         // steps between memory re-sorts
  // Watchdog (see Simulation::step): a step is retried with half the dt when any particle
  // has a non-finite value, moves more than `maxMoveRatio` h in one step, or is compressed
  // beyond `maxDensityError` (relative); after `maxRetries` halvings the run stops.
  Real maxMoveRatio = 0.5;
  Real maxDensityError = 0.5;
  int maxRetries = 6;
};

/// Numbers and vectors by key, with defaults filled in; phase names are stored as phase indices.
struct ParamValues {
  std::map<std::string, std::vector<Real>> params;
  Real number(const std::string& key) const { return params.at(key).at(0); }
  Vec3 vector(const std::string& key) const {
    const auto& v = params.at(key);
    return {v.at(0), v.at(1), v.at(2)};
  }
};

/// Parameters of one enabled effect, and its lists of entries ([[effects.NAME.LIST]]).
struct EffectSpec : ParamValues {
  std::string name;
  std::map<std::string, std::vector<ParamValues>> lists;
  const std::vector<ParamValues>& list(const std::string& key) const {
    static const std::vector<ParamValues> none;
    auto it = lists.find(key);
    return it == lists.end() ? none : it->second;
  }
};

/// The simulation's part of a scene file. Its [surfacing] and [render] tables belong to those stages
/// (surfacing/settings.h, render/settings.h); pipeline/scene_stages.h reads all three.
struct Scene {
  std::string name;
  std::string sourceFile;   // where it came from, for messages
  std::string sourceText;   // the resolved TOML text (overrides applied), for copies
  uint64_t simulationHash = 0;  // hash of the parts the simulation depends on (checkpoint identity)
  Real endTime = 1.0;       // s
  Real frameRate = 30;      // frames per second
  Vec3 domainMin, domainMax;  // particles leaving this box are removed and counted
  uint8_t periodicAxes = 0;   // bit a: the box wraps along axis a (scene.periodic)
  SolverSettings solver;
  std::vector<PhaseSpec> phases;
  std::vector<SolidSpec> solids;
  std::vector<FluidBlockSpec> fluids;
  std::vector<EffectSpec> effects;

  // Where each key was given (dotted path, e.g. "fluid[0].max" -> its line), and which keys
  // came from --set: for messages about the scene as a whole (see scene_budget.h).
  std::map<std::string, int> keyLines;
  std::set<std::string> overriddenKeys;

  int lastFrame() const;  // frames 0 .. lastFrame() at t = f / frameRate
  /// The line of `key`, else of the nearest enclosing table given, else 0.
  int lineOf(const std::string& key) const;
  int phaseIndex(const std::string& name) const;  // -1 if absent
  const EffectSpec* effect(const std::string& name) const;
  PeriodicDomain periodic() const { return {periodicAxes, domainMin, domainMax - domainMin}; }
};

}  // namespace mf
