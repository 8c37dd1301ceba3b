// Bad scene files get errors that name the file, the line, the key and the allowed range.
#include <gtest/gtest.h>

#include <fstream>

#include "sim/scene_file.h"

namespace {

const std::string kGood = R"([scene]
name = "t"
end_time = 1.0
frame_rate = 30
domain_min = [0.0, 0.0, 0.0]
domain_max = [1.0, 1.0, 1.0]
[solver]
pressure = "wcsph"
particle_spacing = 0.05
[[phase]]
name = "water"
rest_density = 1000.0
stiffness = 1000.0
[[fluid]]
phase = "water"
min = [0.0, 0.0, 0.0]
max = [0.5, 0.5, 0.5]
[effects.gravity]
[effects.pressure]
)";

std::vector<mf::SceneProblem> problemsOf(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    mf::parseScene(text, "bad.toml", sets);
  } catch (const mf::SceneError& e) {
    return e.problems();
  }
  return {};
}

std::string replaceLine(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SceneFile, GoodSceneParsesWithDefaults) {
  const mf::Scene s = mf::parseScene(kGood, "good.toml");
  EXPECT_EQ(s.name, "t");
  ASSERT_EQ(s.phases.size(), 1u);
  EXPECT_EQ(s.phases[0].viscosity, 0.0);
  ASSERT_EQ(s.effects.size(), 2u);
  EXPECT_EQ(s.effect("gravity")->vector("acceleration").y, -9.81);
  EXPECT_EQ(s.lastFrame(), 30);
}

TEST(SceneFile, OutOfRangeValueNamesFileLineKeyAndRange) {
  const auto p = problemsOf(replaceLine(kGood, "stiffness = 1000.0", "stiffness = -5.0"));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].file, "bad.toml");
  EXPECT_EQ(p[0].line, 13);
  EXPECT_EQ(p[0].key, "phase[0].stiffness");
  EXPECT_NE(p[0].message.find("(0, 1e+10] m^2/s^2"), std::string::npos) << p[0].message;
  EXPECT_EQ(p[0].str().rfind("bad.toml:13: key 'phase[0].stiffness': value -5 outside the allowed range", 0), 0u) << p[0].str();
}

// DFSPH is the default: a scene that names no solver but carries the state equation's keys was
// written for WCSPH, and is refused rather than run silently on another solver.
TEST(SceneFile, WcsphKeysInASceneThatNamesNoSolverAreRefused) {
  const auto p = problemsOf(replaceLine(kGood, "pressure = \"wcsph\"\n", ""));
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].str().rfind("bad.toml:12: key 'phase[0].stiffness': is read only by the weakly compressible solver", 0), 0u)
      << p[0].str();
  EXPECT_NE(p[0].message.find("set solver.pressure = \"wcsph\""), std::string::npos) << p[0].message;
  EXPECT_EQ(p[1].key, "effects.pressure.reference_density");
  EXPECT_EQ(p[1].line, 18);  // the table's line: the key is missing
  // Named, either way, the scene is the user's choice: DFSPH then leaves the stiffness unread.
  EXPECT_TRUE(problemsOf(kGood).empty());
  EXPECT_TRUE(problemsOf(kGood, {"solver.pressure=\"dfsph\""}).empty());
  // Without them it runs on DFSPH.
  const std::string plain = replaceLine(replaceLine(replaceLine(kGood, "pressure = \"wcsph\"\n", ""), "stiffness = 1000.0\n", ""),
                                        "[effects.pressure]\n", "");
  EXPECT_EQ(mf::parseScene(plain, "plain.toml").solver.pressure, mf::PressureSolverChoice::DFSPH);
}

TEST(SceneFile, EveryProblemIsReported) {
  std::string text = replaceLine(kGood, "frame_rate = 30", "frame_rate = \"fast\"");
  text = replaceLine(text, "phase = \"water\"", "phase = \"oil\"");
  text = replaceLine(text, "particle_spacing = 0.05", "particle_spacing = 0.05\ncfll = 0.3");
  text += "[effects.vorticity]\n";
  const auto p = problemsOf(text);
  ASSERT_EQ(p.size(), 4u);
  std::string all;
  for (const auto& q : p) all += q.str() + "\n";
  EXPECT_NE(all.find("bad.toml:4: key 'scene.frame_rate': expected a number"), std::string::npos) << all;
  EXPECT_NE(all.find("key 'solver.cfll': unknown key"), std::string::npos) << all;
  EXPECT_NE(all.find("key 'fluid[0].phase': unknown phase \"oil\"; defined: \"water\""), std::string::npos) << all;
  EXPECT_NE(all.find("key 'effects.vorticity': unknown effect; known effects: gravity, pressure"), std::string::npos) << all;
}

TEST(SceneFile, SyntaxErrorHasLine) {
  const auto p = problemsOf(replaceLine(kGood, "end_time = 1.0", "end_time = = 1.0"));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].line, 3);
}

TEST(SceneFile, MissingRequiredKeyAndBadGeometry) {
  std::string text = replaceLine(kGood, "max = [0.5, 0.5, 0.5]", "max = [0.5, -0.5, 0.5]");
  text = replaceLine(text, "particle_spacing = 0.05", "");
  const auto p = problemsOf(text);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].key, "solver.particle_spacing");
  EXPECT_NE(p[0].message.find("missing"), std::string::npos);
  EXPECT_EQ(p[1].key, "fluid[0].max");
}

TEST(SceneFile, OverridesApplyAndAreValidated) {
  const mf::Scene s = mf::parseScene(kGood, "good.toml", {"solver.cfl=0.25", "phase.water.viscosity=0.5",
                                                           "solver.density_formulation=number"});
  EXPECT_EQ(s.solver.cfl, 0.25);
  EXPECT_EQ(s.phases[0].viscosity, 0.5);
  EXPECT_EQ(s.solver.density, mf::DensityFormulation::Number);
  EXPECT_NE(s.sourceText.find("0.25"), std::string::npos);  // the resolved text carries overrides

  const auto p = problemsOf(kGood, {"solver.cfl=50"});
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].line, 0);  // came from --set, not from a line of the file
  EXPECT_EQ(p[0].str().rfind("bad.toml (--set): key 'solver.cfl'", 0), 0u) << p[0].str();
  EXPECT_EQ(problemsOf(kGood, {"phase.oil.viscosity=1"}).size(), 1u);
  EXPECT_EQ(problemsOf(kGood, {"nonsense"}).size(), 1u);
}

// A hydrostatic reference without gravity would silently do nothing: it is an error that names
// the key, and with gravity it parses.
TEST(SceneFile, HydrostaticReferenceNeedsGravity) {
  const std::string reference = "[effects.pressure]\nreference_density = 1000.0\nreference_level = 0.4\n";
  const mf::Scene s = mf::parseScene(replaceLine(kGood, "[effects.pressure]\n", reference), "good.toml");
  EXPECT_EQ(s.effect("pressure")->number("reference_density"), 1000.0);
  const auto p = problemsOf(replaceLine(replaceLine(kGood, "[effects.pressure]\n", reference), "[effects.gravity]\n", ""));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].key, "effects.pressure.reference_density");
  EXPECT_NE(p[0].message.find("has no effect without [effects.gravity]"), std::string::npos) << p[0].message;
}

// A reference that follows the content is measured per container, needs the liquid's density,
// and does not read a fixed level: each mistake is an error naming its key.
TEST(SceneFile, ReferenceFollowingTheContentNeedsAContainerAndADensity) {
  auto problems = [&](const std::string& table, const std::string& solid) {
    return problemsOf(replaceLine(kGood, "[effects.pressure]\n", "[effects.pressure]\n" + table) + solid);
  };
  const std::string glass = "[[solid]]\nshape = \"cylinder\"\nbase = [0.0, 0.0, 0.0]\nradius = 0.1\nheight = 0.3\n";
  EXPECT_TRUE(problems("reference_density = 1000.0\nfollow_content = 1\n", glass).empty());
  auto p = problems("reference_density = 1000.0\nfollow_content = 1\n", "");
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].key, "effects.pressure.follow_content");
  EXPECT_NE(p[0].message.find("needs a container"), std::string::npos) << p[0].message;
  p = problems("follow_content = 1\n", glass);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p[0].message.find("needs reference_density"), std::string::npos) << p[0].message;
  p = problems("reference_density = 1000.0\nreference_level = 0.2\nfollow_content = 1\n", glass);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].key, "effects.pressure.reference_level");
}

TEST(SceneFile, EmbeddedScenesAreValid) {
  const auto names = mf::embeddedSceneNames();
  ASSERT_GE(names.size(), 2u);
  for (const auto& n : names) EXPECT_NO_THROW(mf::loadScene(n)) << n;
  EXPECT_THROW(mf::loadScene("/no/such/file.toml"), mf::SceneError);
}

}  // namespace
