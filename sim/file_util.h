// Writing files so that nothing half-written is ever seen, and VDB files whose bytes depend only
// on their content. Plain strings only: no OpenVDB types in sim/ headers.
#pragma once

#include <string>

namespace mf {

/// Writes `bytes` to `path + ".tmp"`, then renames it to `path`.
void writeFileAtomically(const std::string& path, const std::string& bytes);

/// OpenVDB writes a random UUID near the start of every file; this replaces it with one derived
/// from the rest of the bytes, so equal grids give equal files. Throws if no UUID is found.
void makeVdbUuidDeterministic(std::string& vdbBytes);

}  // namespace mf
