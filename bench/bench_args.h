// The benches' command-line lists: "a,b,c" as {"a", "b", "c"}.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace mf::bench {

inline std::vector<std::string> splitCommas(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) v.push_back(item);
  return v;
}

}  // namespace mf::bench
