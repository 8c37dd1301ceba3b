// The scenes of `report stability`'s sweeps (report_stability.cpp) that are its own; the drop in a
// closed box is sim/diagnostics' closedBoxScene, shared with the tests.
#pragma once

#include <string>

namespace mf::report {

/// Heavy water below a lighter fluid at rest (rest densities 1000 and 1000/ratio), one density
/// formulation; the light layer sits on the heavy one through the interface.
std::string layersText(double ratio, const std::string& formulation, double endTime);

/// Water (thermal expansion 1e-3/K, like the lava lamp's) at rest at 20 degrees, heated from
/// below by a source at 20 + range/2 and cooled from above by one at 20 - range/2 (rate 5/s):
/// the rest density changes under the fluid while it convects.
std::string temperatureText(double range, double endTime);

/// A 10 cm cube of water (water's viscosity 1e-3 Pa s, k = 1000 for WCSPH; 1 000 particles at
/// 1 cm spacing) at rest with no gravity and surface tension sigma (N/m): the tension pulls the
/// corners in and the cube rings as a ball. The sharpest start tension can have: the corners'
/// curvature is that of the lattice.
std::string tensionCubeText(double sigma, double spacing, double endTime);

}  // namespace mf::report
