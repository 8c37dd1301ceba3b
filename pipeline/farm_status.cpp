// `multifluid farm status DIR`: what the records say is done, what Slurm says the jobs are doing,
// and why a failed task failed (from its log).
#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "pipeline/farm.h"
#include "pipeline/process.h"
#include "pipeline/run_folder.h"

namespace fs = std::filesystem;

namespace mf::pipeline {

namespace {

struct TaskState {
  std::string state;   // COMPLETED, FAILED, RUNNING, PENDING (reason), ...
  bool failed = false;
  std::string error;   // from the log, for a failed task
  fs::path log;
};

/// The stage's records, as the stages name them.
std::string recordStage(const std::string& stage) { return stage == "sim" ? "particles" : stage; }

/// Finished jobs by sacct, where the cluster keeps accounting; empty (and `note` says why) where not.
std::map<std::string, std::string> accountedJobs(const std::string& list, std::string& note) {
  std::map<std::string, std::string> a;
  ProgramOutput r;
  try {
    r = captureProgram({"sacct", "--noheader", "--parsable2", "--allocations", "--jobs", list, "--format", "JobID,State,ExitCode"});
  } catch (const std::exception& e) {
    note = e.what();
    return a;
  }
  if (r.status != 0) {
    note = "sacct: " + r.err.substr(0, r.err.find('\n'));
    return a;
  }
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string p; std::getline(ls, p, '|');) f.push_back(p);
    if (f.size() >= 3) a[f[0]] = f[1] + " exit " + f[2];
  }
  return a;
}

/// The last exit status the task script logged ("multifluid farm: exit status N"), -1 if none,
/// and the error: the last line multifluid printed as one (else the last line before the status).
int readTaskLog(const fs::path& log, std::string& error) {
  std::ifstream in(log);
  int status = -1;
  std::string lastError, lastLine;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("multifluid farm: exit status ", 0) == 0) {
      status = std::atoi(line.c_str() + 29);
      error = !lastError.empty() ? lastError : lastLine;
      lastError.clear();
      continue;
    }
    if (line.rfind("multifluid farm:", 0) == 0 || line.empty()) continue;
    if (line.rfind("multifluid:", 0) == 0 || line.find("error") != std::string::npos) lastError = line;
    lastLine = line;
  }
  if (status < 0) error = !lastError.empty() ? lastError : lastLine;
  return status;
}

bool failedState(const std::string& s) {
  for (const char* bad : {"FAILED", "TIMEOUT", "OUT_OF_MEMORY", "NODE_FAIL", "BOOT_FAIL", "DEADLINE", "CANCELLED"})
    if (s.rfind(bad, 0) == 0) return true;
  return false;
}

}  // namespace

int farmStatus(const fs::path& dir) {
  const FarmJobs jobs = readFarmJobs(dir);
  const FrameRecords records(dir);
  const int wanted = jobs.lastFrame - jobs.firstFrame + 1;
  fmt::print("farm run {}: scene {}, frames {}-{}, {} frame(s) per task\n", dir.string(), jobs.scene, jobs.firstFrame,
             jobs.lastFrame, jobs.framesPerTask);
  std::string done = "frames done:";
  for (const char* stage : {"particles", "surface", "render"}) {
    int n = 0;
    for (int f = jobs.firstFrame; f <= jobs.lastFrame; ++f) n += records.verify(stage, f) ? 1 : 0;
    done += fmt::format(" {} {}/{}", stage, n, wanted);
  }
  std::error_code ec;
  const fs::path movie = dir / (jobs.scene + ".mp4");
  fmt::print("{}; movie {}\n", done, fs::is_regular_file(movie, ec) ? movie.string() : std::string("not yet"));

  std::vector<std::string> ids;
  for (const auto& [stage, id] : jobs.jobs) ids.push_back(id);
  std::string note, list;
  for (const auto& id : ids) list += (list.empty() ? "" : ",") + id;
  std::map<std::string, std::string> queued;
  try {
    queued = queuedJobs(ids);
  } catch (const std::exception& e) {
    note = e.what();
  }
  const auto accounted = accountedJobs(list, note);

  std::vector<std::string> failures;
  for (const auto& [stage, id] : jobs.jobs) {
    const bool array = stage == "surface" || stage == "render";
    const int tasks = array ? jobs.tasks() : 1;
    std::map<std::string, int> counts;
    for (int t = 0; t < tasks; ++t) {
      const std::string key = array ? fmt::format("{}_{}", id, t) : id;
      TaskState ts;
      ts.log = dir / "farm" / "logs" / fmt::format("{}-{}.log", stage, key);
      std::string error;
      const int logged = readTaskLog(ts.log, error);
      if (const auto q = queued.find(key); q != queued.end()) {
        const size_t bar = q->second.find('|');
        const std::string reason = bar == std::string::npos ? "" : q->second.substr(bar + 1);
        ts.state = q->second.substr(0, bar) + (reason.empty() || reason == "None" ? "" : " (" + reason + ")");
      } else if (const auto a = accounted.find(key); a != accounted.end()) {
        ts.state = a->second;
        ts.failed = failedState(a->second);
      } else if (logged >= 0) {
        ts.state = logged == 0 ? "COMPLETED" : fmt::format("FAILED exit {}", logged);
        ts.failed = logged != 0;
      } else {
        ts.state = fs::exists(ts.log, ec) ? "ENDED without an exit status (killed?)"
                                          : "NOT RUN (neither queued nor logged: cancelled, or its dependency failed)";
        ts.failed = fs::exists(ts.log, ec);
      }
      ++counts[ts.state];
      if (!ts.failed) continue;
      // The frame: the first of the task's frames whose record does not verify.
      const int a = array ? jobs.firstFrame + t * jobs.framesPerTask : jobs.firstFrame;
      const int b = array ? std::min(jobs.lastFrame, a + jobs.framesPerTask - 1) : jobs.lastFrame;
      int frame = -1;
      for (int f = a; f <= b && frame < 0 && stage != "encode"; ++f)
        if (!records.verify(recordStage(stage), f)) frame = f;
      failures.push_back(fmt::format("{} {} (job {}, frames {}-{}) {}{}: {}\n    log: {}", stage, array ? fmt::format("task {}", t) : "job",
                                     key, a, b, ts.state, frame >= 0 ? fmt::format(" at frame {}", frame) : "",
                                     error.empty() ? "no error in its log" : error, ts.log.string()));
    }
    std::string summary;
    for (const auto& [state, n] : counts) summary += fmt::format("{}{} {}", summary.empty() ? "" : ", ", n, state);
    fmt::print("{:<8} job {:<10} {}\n", stage, id, summary);
  }
  if (!note.empty()) fmt::print("note: {}; the states of finished tasks come from their logs\n", note);
  for (const auto& f : failures) fmt::print("failed: {}\n", f);
  return failures.empty() ? 0 : 1;
}

}  // namespace mf::pipeline
