#include "file_util.h"

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "scene_file.h"

namespace mf {

std::string temporaryName(const std::string& path) { return path + ".tmp"; }

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = temporaryName(path);
  auto fail = [&](const char* what, int fd) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());  // never leave a half-written temporary behind
    throw std::runtime_error(fmt::format("cannot write {}: {} ({})", path, std::strerror(err), what));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("open", -1);
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write", fd);
    done += size_t(n);
  }
  // The data must be on disk before the rename makes it visible under its final name: after a
  // crash, a final name then never points at a file that lost its tail.
  if (::fdatasync(fd) != 0 && errno != EINVAL) fail("fdatasync", fd);
  if (::close(fd) != 0) fail("close", -1);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename", -1);
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
