// Scene files (TOML) to validated Scene values. Every problem is reported with the file, the
// line, the key and the allowed range; all problems of a file are collected, not just the first.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene.h"

namespace mf {

struct SceneProblem {
  std::string file;
  int line = 0;      // 0: no line (a command-line override, or a problem of the whole file)
  std::string key;   // dotted path, e.g. "solver.cfl" or "phase[1].stiffness"
  std::string message;
  bool fromOverride = false;  // the value came from a --set
  std::string str() const;  // "file:line: key 'k': message"
};

class SceneError : public std::runtime_error {
 public:
  explicit SceneError(std::vector<SceneProblem> problems);
  const std::vector<SceneProblem>& problems() const { return problems_; }

 private:
  std::vector<SceneProblem> problems_;
};

/// Parses scene text. `overrides` are "dotted.key=toml-value" strings (like --set) applied
/// before validation; [[phase]] entries can be addressed by name: "phase.water.stiffness=1e4".
/// Throws SceneError listing every problem.
/// The simulation's part of a scene: [surfacing] and [render] are only checked to be tables here;
/// each later stage reads its own (pipeline/scene_stages.h reads them all).
Scene parseScene(const std::string& text, const std::string& sourceName,
                 const std::vector<std::string>& overrides = {});

/// A scene's text and the name messages give it. A path (containing '/' or ending in ".toml") is
/// read as a file (at most 1 MiB; a folder is refused); any other word names an embedded scene.
/// Throws SceneError.
struct SceneSource {
  std::string text, name;
};
SceneSource readSceneSource(const std::string& pathOrName);

/// parseScene of readSceneSource(pathOrName).
Scene loadScene(const std::string& pathOrName, const std::vector<std::string>& overrides = {});

/// Every key path ("solver.cfl", "fluid[0].min") the parser asked for while `parse` ran, given
/// or not, with the default it would take ("0.4", "\"wcsph\"", "true", "[0, 0, 0]"; "" where it
/// has no literal one): what the scene reference must document (its test). Not thread-safe.
std::map<std::string, std::string> keyDefaultsReadBy(const std::function<void()>& parse);

/// Names of the scenes compiled into the program (configs/*.toml at build time).
std::vector<std::string> embeddedSceneNames();
/// The text of an embedded scene, or nullptr.
const char* embeddedSceneText(const std::string& name);

/// Names that become file and folder names (scene, phases, solids): 1-64 characters of letters,
/// digits, '_', '-' and '.', starting with a letter or digit, without "..". Returns "" if `name`
/// is fine, else what is wrong.
std::string checkName(const std::string& name);

/// Stable 64-bit hash of a string (FNV-1a), for scene identity in checkpoints.
uint64_t hashText(const std::string& text);

}  // namespace mf
