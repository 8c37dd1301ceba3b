// Writing files so that nothing half-written is ever seen, and VDB files whose bytes depend only
// on their content. Plain strings only: no OpenVDB types in sim/ headers.
#pragma once

#include <string>

namespace mf {

/// The temporary a file is written under before it is renamed to `path` (in the same folder, so
/// that the rename is atomic; the name contains ".tmp", which a run's clean-up looks for).
std::string temporaryName(const std::string& path);

/// Writes `bytes` to temporaryName(path), checks every write, the flush to disk and the close, and
/// only then renames it to `path`. On any failure the temporary is removed and the error (e.g.
/// "No space left on device") is thrown naming `path`; an existing `path` is left untouched.
void writeFileAtomically(const std::string& path, const std::string& bytes);

/// OpenVDB writes a random UUID near the start of every file; this replaces it with one derived
/// from the rest of the bytes, so equal grids give equal files. Throws if no UUID is found.
void makeVdbUuidDeterministic(std::string& vdbBytes);

}  // namespace mf
