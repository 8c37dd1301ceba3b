// Shared yardsticks of the solver's tests and of `multifluid report stability`: one definition
// of the closed-box scene they run and of the energy they watch, so that the report's figures
// and the tests' limits measure the same thing.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

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

/// A free drop of water (rho0 1000, k 100 for WCSPH, mu 0.01 Pa s, surface tension sigma) of radius
/// R about the origin, in zero gravity, in a domain 1 m wide: the yardstick of bench/drop_bench and
/// of `report accuracy`'s static drop.
std::string freeDropScene(const std::string& solver, double R, double spacing, double sigma, double endTime);

/// A ball of gas (rest density `gasDensity`, added density `addedDensity`, phase "air") of radius
/// R at the centre of a 20 x 40 x 20 cm tank of still water filled to 30 cm, at 1 cm spacing, on
/// DFSPH with the number density: a bubble starting up from rest (docs/pressure_solvers.md,
/// "Light phases: the added density"). R = 0.0055 m holds one particle, 0.025 m 81.
std::string bubbleInTankScene(double gasDensity, double addedDensity, double R);

/// The radius of a ball that holds n particles of volume spacing^3: a seeded drop's size by volume.
double volumeRadius(size_t n, double spacing);

/// The mean position of the particles `in` selects (all of them without it); the origin if none.
Vec3 centroidOf(const ParticleSet& particles, const std::function<bool(size_t)>& in = {});

/// The mean pressure (ParticleSet::mechanicalPressure: on DFSPH both solves') of the particles
/// within `radius` of the particles' centroid; NaN when none is.
double meanPressureNearCentroid(const ParticleSet& particles, double radius);

/// The n = 2 mode about the x axis of the particles `inDrop` selects: Q = sum (x^2 - (y^2 + z^2)/2)
/// about their centroid.
double quadrupoleMoment(const ParticleSet& particles, const std::function<bool(size_t)>& inDrop);

/// Starts a drop of radius R centred at `centre` in its n = 2 mode: inside (inDrop) the mode's
/// potential flow phi = A P2 r^2 about the x axis, outside the decaying one, phi = C P2 / r^3 with
/// C = -2 A R^5 / 3 (the radial velocity continuous at R); A = amplitude omega / 2, so that the
/// surface would move by `amplitude` R at the poles. A sphere moved that way reaches
/// Q = 3 amplitude N R^2 / 5.
void kickQuadrupoleMode(ParticleSet& particles, const std::function<bool(size_t)>& inDrop, const Vec3& centre, double R,
                        double omega, double amplitude);

/// Q = 3 amplitude n R^2 / 5: what kickQuadrupoleMode's flow gives a sphere of n particles.
double kickedQuadrupole(size_t n, double R, double amplitude);

/// The period of a sampled oscillation q(t): the mean spacing of successive maxima and of
/// successive minima, each the extreme of q within `window` either side (samples closer than
/// `window` to either end are not candidates). NaN where no two maxima or two minima were found.
struct Oscillation {
  double period = std::numeric_limits<double>::quiet_NaN();
  size_t maxima = 0, minima = 0;
  double largest = 0;  // the largest |q| among the candidates
};
Oscillation oscillationOf(const std::vector<double>& t, const std::vector<double>& q, double window);

/// What a kicked drop did: rang with a period, came apart (over 1 % of its `seeded` particles gone,
/// `kept` left, or an extreme of Q three times `kicked`, what the kick gives a sphere), or died out
/// (no period, or its extremes under a quarter of `kicked`: noise, not the mode).
enum class KickOutcome { Period, CameApart, DiedOut };
KickOutcome kickOutcome(const Oscillation& o, size_t seeded, size_t kept, double kicked);

/// A number as a TOML float ("1.0", not "1"), 10 significant digits.
std::string tomlReal(double v);

}  // namespace mf
