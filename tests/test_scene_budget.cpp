// Scenes that would crash, hang or silently do nothing are refused before anything is allocated,
// each with the file, line and key to change (sim/scene_budget.h, names in sim/scene_file.cpp).
#include <gtest/gtest.h>

#include "sim/scene_budget.h"
#include "sim/scene_file.h"

namespace {

const std::string kScene = R"([scene]
name = "t"
end_time = 1.0
frame_rate = 30
domain_min = [0.0, 0.0, 0.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
pressure = "wcsph"  # the stiffness bounds the step
particle_spacing = 0.05
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
[[solid]]
name = "glass"
shape = "cylinder"
base = [0.5, 0.0, 0.5]
radius = 0.3
height = 0.5
open_top = true
[[fluid]]
phase = "water"
min = [0.3, 0.05, 0.3]
max = [0.7, 0.4, 0.7]
inside = "glass"
[effects.gravity]
[effects.pressure]
)";

/// The problems of the scene with `sets` applied, from parsing or from the budget.
std::vector<mf::SceneProblem> problems(const std::vector<std::string>& sets, mf::BudgetLimits limits = {}) {
  try {
    const mf::Scene sc = mf::parseScene(kScene, "b.toml", sets);
    mf::checkSceneBudget(sc, limits);
  } catch (const mf::SceneError& e) {
    return e.problems();
  }
  return {};
}

bool names(const std::vector<mf::SceneProblem>& ps, const std::string& key) {
  for (const auto& p : ps)
    if (p.key == key && p.file == "b.toml") return true;
  return false;
}

TEST(SceneBudget, TheShippedShapeOfSceneIsAcceptedAndItsCountIsTheSeedingLattice) {
  const mf::Scene sc = mf::parseScene(kScene, "b.toml");
  const mf::SceneBudget b = mf::checkSceneBudget(sc);
  EXPECT_EQ(b.particles, 8 * 7 * 8);  // the block's lattice, all of it inside the glass
  // A block wider than the glass: of its 12 x 12 columns, those within the 0.3 m radius less
  // the default wall margin of 0.45 spacings (0.0225 m), counted by hand from the lattice
  // x = 0.225 + 0.05 i: 96 columns (112 within 0.3 m, with wall_margin = 0), 7 layers each.
  const mf::Scene wide = mf::parseScene(kScene, "b.toml", {"fluid.0.min=[0.2, 0.05, 0.2]", "fluid.0.max=[0.8, 0.4, 0.8]"});
  EXPECT_EQ(mf::checkSceneBudget(wide).particles, 96 * 7);
  const mf::Scene wideNoMargin =
      mf::parseScene(kScene, "b.toml", {"fluid.0.min=[0.2, 0.05, 0.2]", "fluid.0.max=[0.8, 0.4, 0.8]", "fluid.0.wall_margin=0"});
  EXPECT_EQ(mf::checkSceneBudget(wideNoMargin).particles, 112 * 7);
  EXPECT_GT(b.boundarySamples, 0);
  // Here solver.max_dt (1 ms) is below the sound-speed limit (cfl 0.4 * h 0.1 m / c 31.6 m/s =
  // 1.26 ms): 33.3 steps per 1/30 s frame. With k = 1e4, c = 100 m/s: 0.4 ms, 83.3 steps.
  EXPECT_NEAR(b.stepsPerFrame, 1.0 / 30 / 1e-3, 1e-6);
  const mf::SceneBudget stiff = mf::checkSceneBudget(mf::parseScene(kScene, "b.toml", {"phase.water.stiffness=1e4"}));
  EXPECT_NEAR(stiff.stepsPerFrame, 1.0 / 30 / (0.4 * 0.1 / 100), 1e-6);
  EXPECT_NE(stiff.timeStepLimiter.find("phase[0].stiffness"), std::string::npos);
}

TEST(SceneBudget, BlocksThatSeedNothingAreRefusedNamingTheirKey) {
  // Spacing larger than the block: no lattice point fits.
  EXPECT_TRUE(names(problems({"solver.particle_spacing=0.45"}), "fluid[0].max"));
  // Outside the domain.
  EXPECT_TRUE(names(problems({"fluid.0.min=[2.0, 2.0, 2.0]", "fluid.0.max=[2.5, 2.5, 2.5]", "fluid.0.inside=\"glass\""}),
                    "fluid[0].min"));
  // Inside the glass near its wall (r 0.24-0.29 m of 0.3), with a wall margin of 2 spacings
  // (0.1 m) that leaves no lattice point inside.
  EXPECT_TRUE(names(problems({"fluid.0.min=[0.74, 0.05, 0.45]", "fluid.0.max=[0.79, 0.2, 0.55]", "fluid.0.wall_margin=2"}),
                    "fluid[0].wall_margin"));
  // Reaching above the open glass's rim (y = 0.5) would seed fluid outside the glass.
  EXPECT_TRUE(names(problems({"fluid.0.max=[0.7, 0.8, 0.7]"}), "fluid[0].max"));
}

TEST(SceneBudget, MemoryAndStepBoundsNameTheKeyAndCanBeRaised) {
  // 1e-3 m spacing: about 2e7 particles, 20 GB at 1 KiB each.
  const auto fine = problems({"solver.particle_spacing=0.001"}, {1024.0 * 1024 * 1024, 1e5, false});
  ASSERT_TRUE(names(fine, "solver.particle_spacing"));
  EXPECT_NE(fine[0].message.find("MiB"), std::string::npos);
  // Stiffness 1e10: c = 1e5 m/s, dt 4e-7 s, 8e4 steps per frame... at cfl 0.04 that is 8e5.
  const auto stiff = problems({"phase.water.stiffness=1e10", "solver.cfl=0.04"});
  ASSERT_TRUE(names(stiff, "phase[0].stiffness"));
  EXPECT_GT(stiff[0].line, 0);  // the stiffness line of the file
  EXPECT_TRUE(problems({"phase.water.stiffness=1e10", "solver.cfl=0.04"}, {0, 1e5, true}).empty()) << "--force runs it";
  EXPECT_TRUE(problems({"phase.water.stiffness=1e10", "solver.cfl=0.04"}, {0, 1e7, false}).empty()) << "a higher bound runs it";
}

TEST(SceneNames, NamesThatWouldLeaveTheRunFolderOrReachAShellAreRefused) {
  for (const char* bad : {"x'; touch F; echo '", "$(touch F)", "`id`", "a;b", "../../x", "/abs", "a/b", "..", "", ".hidden",
                          "with space", "comma,name"}) {
    const std::string set = std::string("scene.name=\"") + bad + "\"";
    EXPECT_TRUE(names(problems({set}), "scene.name")) << bad;
  }
  EXPECT_TRUE(names(problems({"phase.water.name=\"wa,ter\"", "fluid.0.phase=\"wa,ter\""}), "phase[0].name"));
  EXPECT_TRUE(names(problems({std::string("scene.name=\"") + std::string(65, 'x') + "\""}), "scene.name"));
  EXPECT_TRUE(problems({"scene.name=\"lava_lamp-2.v3\""}).empty());
}

TEST(SceneFile, SilentNonsenseIsRefused) {
  const std::string mix = R"(
[[fluid]]
phases = ["water", "water"]
fractions = [0.0, 0.0]
min = [0.3, 0.05, 0.3]
max = [0.7, 0.4, 0.7]
inside = "glass"
)";
  try {
    mf::parseScene(kScene + mix, "b.toml");
    ADD_FAILURE() << "fractions [0, 0] accepted";
  } catch (const mf::SceneError& e) {
    EXPECT_TRUE(names(e.problems(), "fluid[1].fractions")) << e.what();
  }
  // Only the message of a key that really came from --set says so.
  const auto ps = problems({"solver.cfl=30"});
  ASSERT_FALSE(ps.empty());
  EXPECT_TRUE(ps[0].fromOverride);
  EXPECT_NE(ps[0].str().find("(--set)"), std::string::npos);
}

}  // namespace
