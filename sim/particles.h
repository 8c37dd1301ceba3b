// Particle state as a structure of arrays (Mueller et al. 2005, Table 1: every particle carries
// its own mass, position, velocity, force, rest density, density, viscosity, stiffness, colour
// fields and temperature). Arrays for optional attributes stay empty unless a scene's effects ask
// for them, so a scene pays in memory and time only for what it uses.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vec3.h"

namespace mf {

/// Optional per-particle attributes; a bit set of these says which are allocated.
enum class Attribute : uint32_t {
  InterfaceColour = 1u << 0,  // c_i, immiscible-fluid colour (interface tension)
  SurfaceColour = 1u << 1,    // c_s, liquid = 1, gas = 0 (surface tension)
  Temperature = 1u << 2,      // T in degrees Celsius
  Dye = 1u << 3,              // a passive concentration (dimensionless) that can diffuse
  DivergencePressure = 1u << 4,  // the divergence solve's pressure (DFSPH warm start)
  Latent = 1u << 5,              // heat taken towards evaporation (phase_change.latent_heat), K
};
using AttributeMask = uint32_t;
constexpr AttributeMask bit(Attribute a) { return static_cast<AttributeMask>(a); }

/// Everything needed to create one particle; optional attributes are ignored if not allocated.
struct ParticleInit {
  uint16_t phase = 0;
  Vec3 position, velocity;
  Real mass = 0, restDensity = 0, viscosity = 0, stiffness = 0;
  Real interfaceColour = 0, surfaceColour = 1, temperature = 0, dye = 0;
};

struct ParticleSet {
  // Always present.
  std::vector<uint64_t> id;       // stable identity, never reused
  std::vector<uint16_t> phase;    // index into the scene's phases
  std::vector<Vec3> position;     // m
  std::vector<Vec3> velocity;     // m/s
  std::vector<Vec3> force;        // N, accumulated by the enabled effects each step
  std::vector<Real> mass;         // kg
  std::vector<Real> restDensity;  // rho0, kg/m^3
  std::vector<Real> density;      // rho, kg/m^3 (eq. 1, or m * number density)
  std::vector<Real> volume;       // V = m/rho (or 1/number density), m^3
  std::vector<Real> pressure;     // Pa: WCSPH P = k (rho - rho0); DFSPH the constant-density solve's
  std::vector<Real> viscosity;    // mu, Pa s
  std::vector<Real> stiffness;    // k, m^2/s^2 (k = c^2, c the speed of sound)
  // Optional (empty unless in `attributes`).
  std::vector<Real> interfaceColour;
  std::vector<Real> surfaceColour;
  std::vector<Real> temperature;
  std::vector<Real> dye;
  std::vector<Real> divergencePressure;  // Pa (solver.pressure = "dfsph")
  std::vector<Real> latent;              // K of the liquid's heat capacity (phase_change.latent_heat)

  AttributeMask attributes = 0;

  size_t size() const { return id.size(); }
  bool has(Attribute a) const { return (attributes & bit(a)) != 0; }
  /// The pressure the step applied to particle i (Pa): under DFSPH the sum of its two solves'
  /// (on a settled column the constant-density solve carries 88 % of rho0 g (H - y), the
  /// divergence-free solve 14 %, together 1.03 inside), else `pressure`.
  Real mechanicalPressure(size_t i) const {
    return has(Attribute::DivergencePressure) ? pressure[i] + divergencePressure[i] : pressure[i];
  }

  /// Allocates the optional arrays in `mask` (existing particles get zeros).
  void enable(AttributeMask mask);
  void reserve(size_t n);
  void append(uint64_t newId, const ParticleInit& p);
  /// Reorders every array: new[i] = old[order[i]].
  void permute(const std::vector<uint32_t>& order);
  /// Removes particles whose flag is non-zero, keeping the relative order of the others.
  size_t removeFlagged(const std::vector<uint8_t>& flags);

  /// Calls f(name, vector&) for every allocated array; used for permutation, removal and
  /// checkpoints so that a new attribute cannot be forgotten in one of them.
  template <class F>
  void forEachArray(F&& f) {
    f("id", id);
    f("phase", phase);
    f("position", position);
    f("velocity", velocity);
    f("force", force);
    f("mass", mass);
    f("restDensity", restDensity);
    f("density", density);
    f("volume", volume);
    f("pressure", pressure);
    f("viscosity", viscosity);
    f("stiffness", stiffness);
    if (has(Attribute::InterfaceColour)) f("interfaceColour", interfaceColour);
    if (has(Attribute::SurfaceColour)) f("surfaceColour", surfaceColour);
    if (has(Attribute::Temperature)) f("temperature", temperature);
    if (has(Attribute::Dye)) f("dye", dye);
    if (has(Attribute::DivergencePressure)) f("divergencePressure", divergencePressure);
    if (has(Attribute::Latent)) f("latent", latent);
  }

  /// Bytes held by all arrays (capacity), for memory reports and tests.
  size_t memoryBytes() const;
  /// The largest rho / rho0 - 1 over the particles (0 for none; negative if all are expanded).
  Real largestCompression() const;
};

}  // namespace mf
