// The warnings a run prints after its summary (sim/run_warnings.h): fluid that left, a phase that
// is mostly gone, and none for a run that kept its fluid.
#include <gtest/gtest.h>

#include "sim/run_warnings.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace {

// A 5 x 5 x 5 cube moving at 1 m/s in zero gravity towards the domain's +x face, 5 cm away.
const char* kLeaving = R"([scene]
name = "leaving"
end_time = 0.2
frame_rate = 10
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.1, 0.1, 0.1]
[solver]
particle_spacing = 0.01
pressure = "dfsph"
[[phase]]
name = "water"
rest_density = 1000.0
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.05, 0.05, 0.05]
velocity = [1.0, 0.0, 0.0]
)";

}  // namespace

TEST(RunWarnings, FluidThatLeavesTheDomainAndAPhaseMostlyGoneAreNamed) {
  mf::Simulation sim(mf::parseScene(kLeaving, "leaving.toml"));
  const std::vector<size_t> seeded = mf::phaseCounts(sim);
  ASSERT_EQ(seeded.at(0), 125u);
  EXPECT_TRUE(mf::runWarnings(sim, seeded).empty());
  sim.advanceTo(0.2);  // 20 cm: every particle is past the face
  const auto w = mf::runWarnings(sim, seeded);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("125 particles (100.0 % of the 125 seeded) left the domain"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("phase \"water\" is down to 0 particles"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("no particle is left"), std::string::npos) << w[2];
}
