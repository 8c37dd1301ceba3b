// Shared yardsticks of the solver's tests and of `multifluid report stability`: one definition
// of the closed-box scene they run and of the energy they watch, so that the report's figures
// and the tests' limits measure the same thing.
#pragma once

#include <string>

#include "vec3.h"

namespace mf {

class Simulation;
struct Scene;
struct ParticleSet;

/// Water (rho0 1000, k 1000, mu 0.1; WCSPH unless overridden) in a closed box 0.1 x 0.2 x 0.1 m, all lengths times
/// `scale`: `still` fills it 0.1 m deep at rest; otherwise a 0.1 m block starts 0.05 m above the
/// floor moving down at 2 m/s (the drop). Speeds and `endTime` are scaled by sqrt(scale) (Froude
/// similarity: the same flow at another size; stiffness, viscosity and time-step rules stay).
std::string closedBoxScene(bool still, double scale = 1, double spacing = 0.01, double endTime = 1.0);

/// Kinetic + gravitational (above the lowest solid's floor) + elastic energy, J. The pressure
/// force is -grad of sum_i m_i k_i (ln(rho_i/rho0_i) + rho0_i/rho_i - 1) (where the pressure is
/// clamped, only where rho > rho0) times the lattice normalisation 1/M of the kernel gradient
/// (Simulation scales the gradient by it), so that is the elastic energy the force stores.
double mechanicalEnergy(const Simulation& sim);

/// The scene's gravity (zero without [effects.gravity]) and the height its potential energy counts
/// from (the lowest solid's base; a datum of the energy budget, not the render stage's table).
Vec3 gravityOf(const Scene& scene);
double potentialDatumOf(const Scene& scene);

/// Rayleigh-Taylor: 6 cm of a fluid of 1000 kg/m^3 (`heavy`) over 6 cm of one of 500 (`light`) in
/// a closed 0.1 x 0.2 x 0.06 m box, mu = 0.5 Pa s and k = 200 (WCSPH) as in two_fluids_mixed, both
/// jittered by 0.1 spacing (seeded) so that the overturn does not wait on rounding noise; no solver
/// named. `reference`: the hydrostatic reference the shipped two-fluid scenes set, the heavy
/// fluid's density with its level where a column of it weighs what both layers weigh (0.09 m).
std::string layeredScene(double spacing, const std::string& densityFormulation, bool reference, double endTime);

/// The layered problem's error. The settled interface lies where as many particles are below it as
/// there are heavy ones (a level that compression does not move); a heavy particle more than half
/// a spacing above it, or a light one more than half a spacing below, is on the wrong side.
struct WrongSide {
  double heavy = 0, light = 0;          // kg on the wrong side
  double heavyMass = 0, lightMass = 0;  // each fluid's total
  double fraction() const { return heavyMass + lightMass > 0 ? (heavy + light) / (heavyMass + lightMass) : 0; }
};
WrongSide massOnTheWrongSide(const ParticleSet& particles, int heavyPhase, double spacing);

/// A number as a TOML float ("1.0", not "1"), 10 significant digits.
std::string tomlReal(double v);

}  // namespace mf
