// Hydrostatic column: after settling, the pressure of the state equation matches
// rho0 g (H - y) away from the free surface and the walls.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

// 20 x 16 x 20 particles: a narrower column is dominated by its walls (particles there lack
// half their neighbours and carry the column differently).
const char* kColumn = R"(
[scene]
name = "hydrostatic"
end_time = 1.0
frame_rate = 10
domain_min = [-0.01, -0.01, -0.01]
domain_max = [0.11, 0.2, 0.11]
[solver]
particle_spacing = 0.005
cfl = 0.4
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
viscosity = 0.5
[[solid]]
shape = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.15, 0.1]
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.08, 0.1]
[effects.gravity]
[effects.pressure]
gradient_correction = 1
[effects.viscosity]
[effects.damping]
rate = 40.0
until = 0.3
)";

TEST(Hydrostatic, SettledPressureMatchesRhoGDepth) {
  const mf::Scene scene = mf::parseScene(kColumn, "hydrostatic");
  mf::Simulation sim(scene);
  const double g = 9.81, rho0 = 1000, width = 0.1, h = sim.kernels().h;
  // The column starts uncompressed, drops onto its own weight and would ring in its vertical
  // acoustic mode (period 4H/c = 13 ms, +-40 % in pressure) for seconds: viscosity hardly
  // damps so long a wave. Velocity damping until 0.3 s relaxes it to rest (it does not move
  // the equilibrium). Then compare the time average over every sub-step of 0.3 s .. 0.7 s
  // over the interior particles of each depth bin (one support radius tall): the remaining
  // particle-scale pressure noise averages out.
  std::map<int, std::pair<double, double>> bins;  // bin -> (sum pressure, sum expected)
  double totalMass = 0;
  for (double m : sim.particles().mass) totalMass += m;
  const double H = totalMass / (rho0 * width * width);  // the weight above y is what p(y) carries
  sim.advanceTo(0.3);
  sim.advanceTo(0.7, [&](const mf::Simulation& s) {
    const auto& ps = s.particles();
    const double dt = s.counters().lastDt;
    for (size_t i = 0; i < ps.size(); ++i) {
      const mf::Vec3 x = ps.position[i];
      if (x.x < h || x.x > width - h || x.z < h || x.z > width - h) continue;
      auto& b = bins[int(std::floor(x.y / h))];
      b.first += dt * ps.pressure[i];
      b.second += dt * rho0 * g * (H - x.y);
    }
  });
  int checked = 0;
  for (const auto& [bin, sums] : bins) {
    const double yLow = bin * h, yHigh = (bin + 1) * h;
    // Away from the bottom wall and the free surface by two support radii: the density sum
    // there is cut off by the missing neighbours, by design of SPH.
    if (yLow < 2 * h - 1e-9 || yHigh > H - 2 * h) continue;
    const double ratio = sums.first / sums.second;
    std::printf("hydrostatic: depth bin y in [%.3f, %.3f): p / (rho0 g (H - y)) = %.4f\n", yLow, yHigh, ratio);
    EXPECT_NEAR(ratio, 1.0, 0.02) << "bin " << yLow << " .. " << yHigh;
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

}  // namespace
