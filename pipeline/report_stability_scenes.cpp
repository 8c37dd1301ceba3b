#include "report_stability_scenes.h"

#include <fmt/format.h>

#include "sim/diagnostics.h"

namespace mf::report {

std::string layersText(double ratio, const std::string& formulation, double endTime) {
  return fmt::format(R"(
[scene]
name = "density_ratio"
end_time = {end}
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.21, 0.11]
[solver]
particle_spacing = 0.01
density_formulation = "{f}"
[[phase]]
name = "heavy"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.1
[[phase]]
name = "light"
rest_density = {light}
stiffness = 1000.0
viscosity = 0.1
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.2, 0.1]
[[fluid]]
phase = "heavy"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.05, 0.1]
[[fluid]]
phase = "light"
min = [0.0, 0.05, 0.0]
max = [0.1, 0.1, 0.1]
[effects.gravity]
[effects.pressure]
[effects.viscosity]
)",
                     fmt::arg("end", tomlReal(endTime)), fmt::arg("f", formulation),
                     fmt::arg("light", tomlReal(1000.0 / ratio)));
}

std::string temperatureText(double range, double endTime) {
  return fmt::format(R"(
[scene]
name = "temperature"
end_time = {end}
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.21, 0.11]
[solver]
particle_spacing = 0.01
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.1
thermal_diffusivity = 2e-4
thermal_expansion = 0.001
reference_temperature = 20.0
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.2, 0.1]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.1, 0.1]
temperature = 20.0
[effects.gravity]
[effects.pressure]
[effects.viscosity]
[effects.heat_diffusion]
[[effects.heat_diffusion.source]]
min = [-1.0, -1.0, -1.0]
max = [1.0, 0.03, 1.0]
temperature = {hot}
rate = 5.0
[[effects.heat_diffusion.source]]
min = [-1.0, 0.07, -1.0]
max = [1.0, 1.0, 1.0]
temperature = {cold}
rate = 5.0
[effects.thermal_expansion]
)",
                     fmt::arg("end", tomlReal(endTime)), fmt::arg("hot", tomlReal(20 + range / 2)),
                     fmt::arg("cold", tomlReal(20 - range / 2)));
}

std::string tensionCubeText(double sigma, double spacing, double endTime) {
  return fmt::format(R"(
[scene]
name = "surface_tension"
end_time = {end}
domain_min = [-0.5, -0.5, -0.5]
domain_max = [0.5, 0.5, 0.5]
[solver]
particle_spacing = {s}
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.001
surface_tension = {sigma}
[[fluid]]
phase = "water"
min = [-0.05, -0.05, -0.05]
max = [0.05, 0.05, 0.05]
[effects.pressure]
[effects.viscosity]
[effects.surface_tension]
)",
                     fmt::arg("end", tomlReal(endTime)), fmt::arg("sigma", tomlReal(sigma)), fmt::arg("s", tomlReal(spacing)));
}

}  // namespace mf::report
