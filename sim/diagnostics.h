// Shared yardsticks of the solver's tests and of `multifluid report stability`: one definition
// of the closed-box scene they run and of the energy they watch, so that the report's figures
// and the tests' limits measure the same thing.
#pragma once

#include <string>

#include "vec3.h"

namespace mf {

class Simulation;
struct Scene;

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

/// The scene's gravity (zero without [effects.gravity]) and the height its energy counts from.
Vec3 gravityOf(const Scene& scene);
double floorHeightOf(const Scene& scene);

/// A number as a TOML float ("1.0", not "1"), 10 significant digits.
std::string tomlReal(double v);

}  // namespace mf
