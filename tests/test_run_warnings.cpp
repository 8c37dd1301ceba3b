// The warnings a run prints after its summary (sim/run_warnings.h): fluid that left, a phase that
// is mostly gone, and none for a run that kept its fluid.
#include <fmt/format.h>
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

// The same cube, now at rest, beside a disc emitting "gas" at 1 m/s towards the domain's top,
// 4 cm above it: the gas leaves, the water stays.
const char* kEmitted = R"([scene]
name = "emitted"
end_time = 0.3
frame_rate = 10
domain_min = [0.0, 0.0, 0.0]
domain_max = [0.1, 0.1, 0.1]
[solver]
particle_spacing = 0.01
pressure = "dfsph"
[[phase]]
name = "water"
rest_density = 1000.0
[[phase]]
name = "gas"
rest_density = 1000.0
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.05, 0.05, 0.05]
[effects.emitter]
[[effects.emitter.disc]]
phase = "gas"
centre = [0.08, 0.06, 0.05]
radius = 0.01
velocity = [0.0, 1.0, 0.0]
)";

}  // namespace

TEST(RunWarnings, AnEmittedPhaseThatLeavesIsNamedAgainstWhatWasBorn) {
  mf::Simulation sim(mf::parseScene(kEmitted, "emitted.toml"));
  const std::vector<size_t> seeded = mf::phaseCounts(sim);
  sim.advanceTo(0.3);
  const uint64_t born = sim.bornByPhase().at(1), left = sim.leftDomainByPhase().at(1);
  ASSERT_GT(born, 0u);
  ASSERT_GT(left, 0u);
  EXPECT_EQ(sim.leftDomainByPhase().at(0), 0u);
  const auto w = mf::runWarnings(sim, seeded);
  ASSERT_EQ(w.size(), 1u) << (w.empty() ? "" : w[0]);
  EXPECT_NE(w[0].find(fmt::format("{} gas particles", left)), std::string::npos) << w[0];
  EXPECT_NE(w[0].find(fmt::format("of the {} it had", born)), std::string::npos) << w[0];
  // The counts survive a checkpoint.
  const std::string path = ::testing::TempDir() + "emitted.ckpt";
  sim.saveCheckpoint(path, 3);
  mf::Simulation resumed(mf::parseScene(kEmitted, "emitted.toml"));
  resumed.loadCheckpoint(path);
  EXPECT_EQ(resumed.leftDomainByPhase(), sim.leftDomainByPhase());
  EXPECT_EQ(resumed.bornByPhase(), sim.bornByPhase());
}

TEST(RunWarnings, FluidThatLeavesTheDomainAndAPhaseMostlyGoneAreNamed) {
  mf::Simulation sim(mf::parseScene(kLeaving, "leaving.toml"));
  const std::vector<size_t> seeded = mf::phaseCounts(sim);
  ASSERT_EQ(seeded.at(0), 125u);
  EXPECT_TRUE(mf::runWarnings(sim, seeded).empty());
  sim.advanceTo(0.2);  // 20 cm: every particle is past the face
  const auto w = mf::runWarnings(sim, seeded);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("125 water particles (100.0 % of the 125 it had, seeded and born) left the domain"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("phase \"water\" is down to 0 particles"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("no particle is left"), std::string::npos) << w[2];
}
