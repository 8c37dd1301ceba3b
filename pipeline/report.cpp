#include "report.h"

#include <fmt/format.h>

namespace mf::report {

int runReportCommand(const std::vector<std::string>&) {
  fmt::print(stderr, "multifluid report: being built (issue 8)\n");
  return 1;
}

}  // namespace mf::report
