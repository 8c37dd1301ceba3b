// `multifluid report accuracy|stability`: error against run time, and stability on stiff and
// extreme cases (issue 8). Writes CSV, PNG plots and a Markdown page into a folder.
#pragma once

#include <string>
#include <vector>

namespace mf::report {

/// Runs the report command; `args` are the words after `report`. Returns the exit status.
int runReportCommand(const std::vector<std::string>& args);

}  // namespace mf::report
