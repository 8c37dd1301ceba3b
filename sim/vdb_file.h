// Integrity of the VDB files the pipeline writes (particle and surface frames). OpenVDB's reader
// trusts its input: on damaged copies of a particle file, OpenVDB 10.0.1 (Debian 12) aborted on
// its assertions, crashed, corrupted its heap, ran past 20 s and allocated gigabytes from sizes
// it read (bad_alloc or the kernel's OOM killer, not an error). So each file carries an
// xxHash of its bytes in its file-level metadata (a plain string, which DCC tools ignore), and
// readers check the size and that hash before OpenVDB sees a byte. Plain strings only: no OpenVDB
// types in sim/ headers.
#pragma once

#include <cstdint>
#include <streambuf>
#include <string>

namespace mf {

/// File-level metadata key; writers store vdbChecksumPlaceholder() under it and sealVdbFile
/// replaces that with the hash.
inline constexpr const char* kVdbChecksumKey = "multifluid_xxh3";
std::string vdbChecksumPlaceholder();

/// Largest VDB file read (checked before reading): about 300 million particles.
inline constexpr uint64_t kMaxVdbFileBytes = uint64_t(16) << 30;

/// Makes the UUID deterministic (makeVdbUuidDeterministic), then fills in the checksum. Throws
/// if the bytes have no placeholder.
void sealVdbFile(std::string& vdbBytes);

/// Reads `path` whole and checks its size and checksum. Errors are std::runtime_error
/// "<path>: not a readable <kind> (<reason>; <remedy>)".
std::string readSealedVdbFile(const std::string& path, const std::string& kind, const std::string& remedy);

/// A library's error text as one printable line of at most 120 characters (OpenVDB's messages
/// can quote raw bytes of a damaged file).
std::string shortErrorText(const char* what);

/// A read-only std::streambuf over bytes in memory (with seeking), to parse them without a copy.
class MemoryInput : public std::streambuf {
 public:
  MemoryInput(const char* data, size_t size);

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override;
};

}  // namespace mf
