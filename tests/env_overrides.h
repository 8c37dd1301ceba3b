// Scene overrides for hand-run trials: the ';'-separated key=value list in an environment
// variable (as --set takes them), empty when the variable is unset.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

namespace mf::test {

inline std::vector<std::string> overridesFromEnv(const char* variable) {
  std::vector<std::string> out;
  const char* value = std::getenv(variable);
  if (!value) return out;
  std::string cur;
  for (const char* c = value;; ++c) {
    if (*c == ';' || *c == '\0') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
      if (*c == '\0') break;
    } else {
      cur += *c;
    }
  }
  return out;
}

}  // namespace mf::test
