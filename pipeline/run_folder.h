// A run folder's bookkeeping: the completion records that say which frames of which stage are
// finished (the locks are in folder_lock.h). A frame counts as done only when its
// record exists and every file it lists has the recorded size and xxHash; anything else is redone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mf::pipeline {

struct FileDigest {
  std::string name;  // relative to the run folder
  uint64_t size = 0;
  uint64_t hash = 0;  // XXH3-64 of the bytes
};

/// Size and XXH3-64 of a file; throws naming the file if it cannot be read.
FileDigest digestFile(const std::filesystem::path& file, const std::string& name);

/// The records of one run folder: DIR/records/<stage>.NNNN.txt, one line per output file.
/// Verified frames are remembered for the life of the object (a frame's owner holds its lock, and
/// a finished upstream frame is only ever rewritten with the same bytes): the summary does not
/// hash every file a second time.
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
