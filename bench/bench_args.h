// The benches' command-line values: "a,b,c" as {"a", "b", "c"}, and numbers read whole, so that
// a typo stops the bench with a message naming the flag instead of being read as 0 or a prefix.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
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

/// The whole of `text` as a finite number, or exit 2 (the benches' usage error) naming `what`.
inline double number(const std::string& what, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    std::fprintf(stderr, "%s: \"%s\" is not a number\n", what.c_str(), text.c_str());
    std::exit(2);
  }
  return v;
}

/// The whole of `text` as a whole number, or exit 2 naming `what`.
inline long whole(const std::string& what, const std::string& text) {
  const double v = number(what, text);
  if (v != std::floor(v) || std::fabs(v) > 1e15) {
    std::fprintf(stderr, "%s: \"%s\" is not a whole number\n", what.c_str(), text.c_str());
    std::exit(2);
  }
  return long(v);
}

/// "a,b,c" as whole numbers, each read whole.
inline std::vector<long> wholeList(const std::string& what, const std::string& text) {
  std::vector<long> v;
  for (const std::string& item : splitCommas(text)) v.push_back(whole(what, item));
  return v;
}

}  // namespace mf::bench
