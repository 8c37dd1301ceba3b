#include "file_util.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "scene_file.h"

namespace mf {

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

void makeVdbUuidDeterministic(std::string& bytes) {
  const size_t searchEnd = std::min<size_t>(bytes.size(), 128);
  for (size_t at = 0; at + 36 <= searchEnd; ++at) {
    bool looksLikeUuid = true;
    for (size_t k = 0; k < 36 && looksLikeUuid; ++k) {
      const char c = bytes[at + k];
      looksLikeUuid = (k == 8 || k == 13 || k == 18 || k == 23) ? c == '-' : std::isxdigit(static_cast<unsigned char>(c)) != 0;
    }
    if (!looksLikeUuid) continue;
    const std::string rest = bytes.substr(0, at) + bytes.substr(at + 36);
    const uint64_t h1 = hashText(rest), h2 = hashText(rest + "#");
    const std::string hex = fmt::format("{:016x}{:016x}", h1, h2);
    const std::string uuid = hex.substr(0, 8) + "-" + hex.substr(8, 4) + "-" + hex.substr(12, 4) + "-" +
                             hex.substr(16, 4) + "-" + hex.substr(20, 12);
    std::memcpy(&bytes[at], uuid.data(), 36);
    return;
  }
  throw std::runtime_error("OpenVDB file header has no UUID where expected");
}

}  // namespace mf
