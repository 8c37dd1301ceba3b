#include "pipeline/run_folder.h"

#include <xxhash.h>

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sim/file_util.h"

namespace fs = std::filesystem;

namespace mf::pipeline {

FileDigest digestFile(const fs::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  FileDigest d{name, 0, 0};
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    XXH3_64bits_update(state, buf.data(), size_t(got));
    d.size += uint64_t(got);
  }
  const bool bad = in.bad();
  d.hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  if (bad) throw std::runtime_error(file.string() + ": read error");
  return d;
}

fs::path FrameRecords::recordFile(const std::string& stage, int frame) const {
  return dir_ / "records" / fmt::format("{}.{:04d}.txt", stage, frame);
}

namespace {
constexpr const char* kHeader = "multifluid completion record 1";

bool readRecord(const fs::path& file, std::vector<FileDigest>& out) {
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) return false;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    FileDigest d;
    std::string hash;
    if (!(ls >> hash >> d.size) || hash.size() != 16) return false;
    std::getline(ls >> std::ws, d.name);
    if (d.name.empty() || d.name.find("..") != std::string::npos || d.name.front() == '/') return false;
    if (std::from_chars(hash.data(), hash.data() + 16, d.hash, 16).ptr != hash.data() + 16) return false;
    out.push_back(d);
  }
  return !out.empty();
}
}  // namespace

bool FrameRecords::verify(const std::string& stage, int frame, std::string* why) const {
  if (const auto it = verified_.find({stage, frame}); it != verified_.end() && it->second) return true;
  const fs::path rec = recordFile(stage, frame);
  std::vector<FileDigest> listed;
  std::error_code ec;
  if (!fs::exists(rec, ec)) {
    if (why) *why = "no completion record " + rec.string();
    return false;
  }
  if (!readRecord(rec, listed)) {
    if (why) *why = "unreadable completion record " + rec.string();
    return false;
  }
  for (const FileDigest& d : listed) {
    const fs::path file = dir_ / d.name;
    if (!fs::is_regular_file(file, ec)) {
      if (why) *why = file.string() + " is missing";
      return false;
    }
    if (fs::file_size(file, ec) != d.size) {
      if (why) *why = fmt::format("{} has {} bytes; its record says {}", file.string(), fs::file_size(file, ec), d.size);
      return false;
    }
    if (digestFile(file, d.name).hash != d.hash) {
      if (why) *why = file.string() + " does not match the hash in its record (damaged)";
      return false;
    }
  }
  verified_[{stage, frame}] = true;
  return true;
}

void FrameRecords::write(const std::string& stage, int frame, const std::vector<fs::path>& files) const {
  std::string text = std::string(kHeader) + "\n";
  for (const fs::path& f : files) {
    const std::string name = fs::relative(f, dir_).generic_string();
    const FileDigest d = digestFile(f, name);
    text += fmt::format("{:016x} {} {}\n", d.hash, d.size, d.name);
  }
  fs::create_directories(dir_ / "records");
  writeFileAtomically(recordFile(stage, frame).string(), text);
  verified_[{stage, frame}] = true;
}

void FrameRecords::remove(const std::string& stage, int frame) const {
  verified_.erase({stage, frame});
  std::error_code ec;
  fs::remove(recordFile(stage, frame), ec);
}

std::vector<fs::path> FrameRecords::files(const std::string& stage, int frame) const {
  std::vector<FileDigest> listed;
  std::vector<fs::path> out;
  if (readRecord(recordFile(stage, frame), listed))
    for (const auto& d : listed) out.push_back(dir_ / d.name);
  return out;
}

}  // namespace mf::pipeline
