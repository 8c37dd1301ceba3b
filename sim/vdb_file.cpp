#include "vdb_file.h"

#include <fmt/format.h>
#include <xxhash.h>

#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "file_util.h"

namespace mf {

namespace {

constexpr size_t kDigits = 16;
// The file-level metadata comes right after OpenVDB's fixed header (about 60 bytes).
constexpr size_t kSearchBytes = 4096;

void putU32(std::string& o, uint32_t v) { o.append(reinterpret_cast<const char*>(&v), sizeof v); }

// How OpenVDB writes a string metadata entry: name, type name and value size, each length-prefixed.
std::string checksumEntryPrefix() {
  std::string p;
  putU32(p, uint32_t(std::strlen(kVdbChecksumKey)));
  p += kVdbChecksumKey;
  putU32(p, 6);
  p += "string";
  putU32(p, uint32_t(kDigits));
  return p;
}

// Where the hash's digits are, or npos.
size_t findDigits(std::string_view bytes) {
  const std::string prefix = checksumEntryPrefix();
  const size_t at = bytes.substr(0, kSearchBytes).find(prefix);
  if (at == std::string_view::npos || at + prefix.size() + kDigits > bytes.size()) return std::string_view::npos;
  return at + prefix.size();
}

// XXH3 of the bytes with the digits read as the placeholder's zeros.
uint64_t sealHash(std::string_view bytes, size_t digits) {
  XXH3_state_t* state = XXH3_createState();
  if (!state) throw std::bad_alloc();
  const std::string zeros = vdbChecksumPlaceholder();
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, bytes.data(), digits);
  XXH3_64bits_update(state, zeros.data(), kDigits);
  XXH3_64bits_update(state, bytes.data() + digits + kDigits, bytes.size() - digits - kDigits);
  const uint64_t h = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return h;
}

}  // namespace

std::string vdbChecksumPlaceholder() { return std::string(kDigits, '0'); }

void sealVdbFile(std::string& bytes) {
  makeVdbUuidDeterministic(bytes);
  const size_t digits = findDigits(bytes);
  if (digits == std::string::npos || bytes.compare(digits, kDigits, vdbChecksumPlaceholder()) != 0)
    throw std::logic_error("sealVdbFile: no checksum placeholder in the file-level metadata");
  const std::string hex = fmt::format("{:016x}", sealHash(bytes, digits));
  std::memcpy(&bytes[digits], hex.data(), kDigits);
}

std::string readSealedVdbFile(const std::string& path, const std::string& kind, const std::string& remedy) {
  auto fail = [&](const std::string& why) {
    return std::runtime_error(path + ": not a readable " + kind + " (" + why + "; " + remedy + ")");
  };
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error(path + ": cannot read " + kind + " (" + ec.message() + ")");
  if (size > kMaxVdbFileBytes) throw fail(fmt::format("{} bytes, more than the limit of {} GiB", size, kMaxVdbFileBytes >> 30));
  std::string bytes(size_t(size), '\0');
  {
    std::ifstream in(path, std::ios::binary);
    if (!in.read(bytes.data(), std::streamsize(bytes.size())) || in.peek() != std::char_traits<char>::eof())
      throw std::runtime_error(path + ": cannot read " + kind + " (read error, or the file changed while being read)");
  }
  const size_t digits = findDigits(bytes);
  if (digits == std::string::npos)
    throw fail("no multifluid checksum: damaged, cut short, or not written by this version of multifluid");
  uint64_t stored = 0;
  const char* first = bytes.data() + digits;
  const auto parsed = std::from_chars(first, first + kDigits, stored, 16);
  if (parsed.ec != std::errc() || parsed.ptr != first + kDigits || sealHash(bytes, digits) != stored)
    throw fail("checksum mismatch: the file is damaged");
  return bytes;
}

std::string shortErrorText(const char* what) {
  std::string s;
  for (const char* c = what; *c && s.size() < 120; ++c) s += (*c >= 32 && *c < 127) ? *c : '?';
  return s;
}

MemoryInput::MemoryInput(const char* data, size_t size) {
  char* p = const_cast<char*>(data);  // the get area is only read
  setg(p, p, p + size);
}

MemoryInput::pos_type MemoryInput::seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) {
  if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
  const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? gptr() - eback() : egptr() - eback();
  const off_type to = base + off;
  if (to < 0 || to > egptr() - eback()) return pos_type(off_type(-1));
  setg(eback(), eback() + to, egptr());
  return pos_type(to);
}

MemoryInput::pos_type MemoryInput::seekpos(pos_type pos, std::ios_base::openmode which) {
  return seekoff(off_type(pos), std::ios_base::beg, which);
}

}  // namespace mf
