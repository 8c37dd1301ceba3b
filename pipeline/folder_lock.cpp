#include "pipeline/folder_lock.h"

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/file_util.h"

namespace fs = std::filesystem;

namespace mf::pipeline {

std::string LockScope::describe() const {
  return whole() ? stage + " stage" : fmt::format("{} stage, frames {}-{}", stage, first, last);
}

namespace {

fs::path pidFile(const fs::path& dir, const std::string& stage, long start, long len) {
  if (len <= 0) return dir / "locks" / (stage + ".pid");
  return dir / "locks" / fmt::format("{}.{:04d}-{:04d}.pid", stage, start, start + len - 1);
}

std::string readPid(const fs::path& file) {
  std::ifstream in(file);
  std::string pid;
  return in >> pid ? pid : std::string("unknown");
}

}  // namespace

FolderLocks::FolderLocks(const fs::path& dir, std::vector<LockScope> scopes) : dir_(dir), scopes_(std::move(scopes)) {
  fs::create_directories(dir_ / "locks");
  try {
    for (const LockScope& s : scopes_) {
      const fs::path file = dir_ / "locks" / (s.stage + ".lock");
      const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd < 0) throw std::runtime_error(fmt::format("cannot open {}: {}", file.string(), std::strerror(errno)));
      fds_.push_back(fd);
      struct flock fl {};
      fl.l_type = F_WRLCK;
      fl.l_whence = SEEK_SET;
      fl.l_start = s.whole() ? 0 : s.first;
      fl.l_len = s.whole() ? 0 : s.last - s.first + 1;  // 0: to the end of the file and beyond
      if (::fcntl(fd, F_OFD_SETLK, &fl) != 0) {
        const int err = errno;
        if (err != EAGAIN && err != EACCES)
          throw std::runtime_error(fmt::format("cannot lock {}: {}", file.string(), std::strerror(err)));
        // The holder's range names its PID file (OFD locks report no PID themselves).
        struct flock held = fl;
        std::string pid = "unknown", what = s.describe();
        if (::fcntl(fd, F_OFD_GETLK, &held) == 0 && held.l_type != F_UNLCK) {
          pid = readPid(pidFile(dir_, s.stage, held.l_start, held.l_len));
          what = held.l_len == 0 ? LockScope{s.stage}.describe()
                                 : LockScope{s.stage, int(held.l_start), int(held.l_start + held.l_len - 1)}.describe();
        }
        throw std::runtime_error(fmt::format(
            "{} is in use by another multifluid run (PID {}), which holds its {}; wait for it to end or choose another --out",
            dir_.string(), pid, what));
      }
      const fs::path pf = pidFile(dir_, s.stage, fl.l_start, fl.l_len);
      writeFileAtomically(pf.string(), fmt::format("{}\n", ::getpid()));
      pidFiles_.push_back(pf);
    }
  } catch (...) {
    for (const fs::path& pf : pidFiles_) fs::remove(pf);
    for (const int fd : fds_) ::close(fd);
    throw;
  }
}

FolderLocks::~FolderLocks() {
  std::error_code ec;
  for (const fs::path& pf : pidFiles_) fs::remove(pf, ec);  // while still locked: no one else's
  for (const int fd : fds_) ::close(fd);                    // closing drops the locks
}

namespace {

/// The frame a file name carries: its last all-digit dot-separated part ("water.0003.ply.tmp"), or -1.
int frameOf(const std::string& name) {
  int frame = -1;
  std::stringstream parts(name);
  for (std::string p; std::getline(parts, p, '.');)
    if (!p.empty() && p.size() <= 7 && p.find_first_not_of("0123456789") == std::string::npos) frame = std::stoi(p);
  return frame;
}

bool isTemporary(const fs::directory_entry& e) {
  std::error_code ec;
  return e.is_regular_file(ec) && e.path().filename().string().find(".tmp") != std::string::npos;
}

}  // namespace

int removeStaleTemporaries(const fs::path& dir, const FolderLocks& locks) {
  int removed = 0;
  std::error_code ec;
  auto removeIn = [&](const fs::path& d, auto&& owned) {
    if (!fs::is_directory(d, ec)) return;
    for (const auto& e : fs::directory_iterator(d, ec))
      if (isTemporary(e) && owned(e.path().filename().string()) && fs::remove(e.path(), ec)) ++removed;
  };
  for (const LockScope& s : locks.scopes()) {
    auto inRange = [&s](const std::string& name) {
      const int f = frameOf(name);
      return s.whole() || (f >= s.first && f <= s.last);
    };
    const std::string recordStage = s.stage == "sim" ? "particles" : s.stage;
    std::vector<std::string> folders;
    if (s.stage == "sim") folders = {"particles"};
    else if (s.stage == "surface") folders = {"surface", "mesh"};
    else if (s.stage == "render" || s.stage == "preview") folders = {s.stage};
    for (const std::string& f : folders) removeIn(dir / f, inRange);
    removeIn(dir / "records", [&](const std::string& name) { return name.rfind(recordStage + ".", 0) == 0 && inRange(name); });
    if (s.stage == "sim")
      removeIn(dir, [](const std::string& name) { return name == "checkpoint.bin.tmp" || name.rfind("scene.toml.tmp", 0) == 0; });
    if (s.stage == "encode")
      removeIn(dir, [](const std::string& name) { return name.size() > 8 && name.compare(name.size() - 8, 8, ".tmp.mp4") == 0; });
  }
  return removed;
}

}  // namespace mf::pipeline
