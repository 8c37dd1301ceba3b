// Who works on what in a run folder. A farm runs the simulation, surfacing tasks and rendering
// tasks in one folder at the same time, so a process locks only the stages and frames it writes:
// two processes on the same stage and overlapping frames are still refused, naming the holder.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mf::pipeline {

/// A stage and the frames of it that a process writes. `first` -1: the whole stage (sim, whose
/// checkpoint serves every frame, and encode, whose movie does).
struct LockScope {
  std::string stage;  // sim, surface, render, preview, encode
  int first = -1, last = -1;
  bool whole() const { return first < 0; }
  std::string describe() const;
};

/// Exclusive open-file-description locks on byte ranges of DIR/locks/<stage>.lock (byte f is
/// frame f; a whole stage locks the file to its end) for the life of the object. The kernel drops
/// them when the process ends, even by SIGKILL, so a killed run never leaves frames locked; OFD
/// locks are fcntl locks, which NFS carries to the server, unlike flock on some systems. The
/// owner's PID goes to DIR/locks/<stage>.<frames>.pid, so that a refusal can name it.
class FolderLocks {
 public:
  FolderLocks(const std::filesystem::path& dir, std::vector<LockScope> scopes);
  ~FolderLocks();
  FolderLocks(const FolderLocks&) = delete;
  FolderLocks& operator=(const FolderLocks&) = delete;
  const std::vector<LockScope>& scopes() const { return scopes_; }

 private:
  std::filesystem::path dir_;
  std::vector<LockScope> scopes_;
  std::vector<int> fds_;
  std::vector<std::filesystem::path> pidFiles_;
};

/// Removes the temporaries (names containing ".tmp") that a killed run left in what `locks`
/// covers: the stages' folders and records, for the locked frames only, and the root files of
/// the stages locked whole (sim: checkpoint and scene copy; encode: the movie). Another live
/// process's temporaries are never touched. Returns how many were removed.
int removeStaleTemporaries(const std::filesystem::path& dir, const FolderLocks& locks);

}  // namespace mf::pipeline
