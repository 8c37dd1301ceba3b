// A run folder's bookkeeping: the lock that keeps two runs out of one folder, and the completion
// records that say which frames of which stage are finished. A frame counts as done only when its
// record exists and every file it lists has the recorded size and xxHash; anything else is redone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mf::pipeline {

/// An exclusive flock on DIR/run.lock for the life of the object; the file holds the owner's PID.
/// A second run into the same folder is refused with that PID. The kernel drops the lock when the
/// process ends, even by SIGKILL, so a killed run never leaves the folder locked.
class RunLock {
 public:
  explicit RunLock(const std::filesystem::path& dir);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

/// Removes the temporaries (names containing ".tmp") a killed run left in `dir` and its stage
/// folders. Only called while the lock is held, so no live run owns them. Returns how many.
int removeStaleTemporaries(const std::filesystem::path& dir);

struct FileDigest {
  std::string name;  // relative to the run folder
  uint64_t size = 0;
  uint64_t hash = 0;  // XXH3-64 of the bytes
};

/// Size and XXH3-64 of a file; throws naming the file if it cannot be read.
FileDigest digestFile(const std::filesystem::path& file, const std::string& name);

/// The records of one run folder: DIR/records/<stage>.NNNN.txt, one line per output file.
/// Verified frames are remembered for the life of the object (the run holds the folder's lock,
/// so nothing else changes them): the summary does not hash every file a second time.
class FrameRecords {
 public:
  explicit FrameRecords(std::filesystem::path dir) : dir_(std::move(dir)) {}

  std::filesystem::path recordFile(const std::string& stage, int frame) const;
  /// True when the record exists and matches every file it lists; else `why` says what failed.
  bool verify(const std::string& stage, int frame, std::string* why = nullptr) const;
  /// Digests `files` (paths inside the run folder) and writes the record, last and atomically.
  void write(const std::string& stage, int frame, const std::vector<std::filesystem::path>& files) const;
  /// Deletes the record, so that the frame counts as not done (before its files are rewritten).
  void remove(const std::string& stage, int frame) const;
  /// The files a record lists (full paths), or none if there is no readable record.
  std::vector<std::filesystem::path> files(const std::string& stage, int frame) const;

 private:
  std::filesystem::path dir_;
  mutable std::map<std::pair<std::string, int>, bool> verified_;
};

}  // namespace mf::pipeline
