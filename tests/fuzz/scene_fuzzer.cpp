// libFuzzer target: mf::parseSceneStages (every stage's tables), then the budget check (mf::checkSceneBudget) of a scene it
// accepts, on arbitrary bytes. A scene the reader refuses must be refused
// with mf::SceneError, every problem of which names the file; anything else (another exception,
// a crash, a sanitizer report, a timeout, memory over the limit) is a bug.
// Built and run by tests/fuzz_parser.sh; corpus in tests/fuzz/corpus/.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pipeline/scene_stages.h"
#include "sim/scene_budget.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kFile = "fuzz.toml";
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mf::SceneStages s = mf::parseSceneStages(text, kFile);
    mf::checkSceneBudget(s.scene, {}, s.laterSizes());
  } catch (const mf::SceneError& e) {
    if (e.problems().empty()) {
      std::fprintf(stderr, "SceneError with no problem\n");
      std::abort();
    }
    for (const mf::SceneProblem& p : e.problems())
      if (p.file != kFile || p.str().compare(0, kFile.size(), kFile) != 0) {
        std::fprintf(stderr, "problem that does not name the file: %s\n", p.str().c_str());
        std::abort();
      }
  }
  return 0;
}
