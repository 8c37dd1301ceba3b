// multifluid on a Slurm farm: `farm submit` writes sbatch scripts into DIR/farm and submits the
// simulation (one requeue-able job), surfacing and rendering (job arrays over the frames) and
// encoding, chained by dependencies; `farm status` and `farm cancel` read the job ids it
// recorded. Slurm's commands are started with an argument vector (process.h), never a shell, and
// the scripts take every user string (run folder, scene) as an argument, never as script text.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sim/scene.h"

namespace mf::pipeline {

struct FarmSubmitOptions {
  std::filesystem::path out;            // the run folder (absolute): on storage every node shares
  std::vector<std::string> stages = {"sim", "surface", "render", "encode"};
  int firstFrame = 0, lastFrame = 0;    // resolved against the scene
  int framesPerTask = 1;
  int cpusPerTask = 1;
  double waitForInputSeconds = 300;     // a task's wait for its input frame's record, per start
  std::string partition, timeLimit;     // "" = the cluster's defaults
  int timeLimitSeconds = 0;             // timeLimit parsed (0 = none)
  std::vector<std::string> passOptions; // --max-memory, --max-steps-per-frame, --force as given
  bool dryRun = false;
};

/// Writes DIR/farm/scene.toml (the scene as resolved, overrides applied: every task reads this
/// one copy), the scripts, and submits them; records the job ids in DIR/farm/jobs.txt. Prints the
/// sbatch command lines (only those, with --dry-run, which submits nothing). Returns 0 or throws.
int farmSubmit(const Scene& scene, const FarmSubmitOptions& options);

/// Frames done per stage (by completion records), the jobs' states (squeue, sacct where Slurm
/// keeps accounting, else the tasks' logs) and, for a failed task, its frame and error.
/// Returns 0, or 1 when a task has failed.
int farmStatus(const std::filesystem::path& dir);

/// scancel of the recorded jobs. Returns scancel's status.
int farmCancel(const std::filesystem::path& dir);

/// Slurm's time formats (M, M:S, H:M:S, D-H, D-H:M, D-H:M:S) in seconds, or -1 if malformed.
int parseSlurmTime(const std::string& t);

// --- shared by submit and status --------------------------------------------------------------

/// DIR/farm/jobs.txt: what was submitted.
struct FarmJobs {
  std::string scene;
  int firstFrame = 0, lastFrame = 0, framesPerTask = 1;
  std::vector<std::pair<std::string, std::string>> jobs;  // stage -> job id, in submission order
  int tasks() const { return (lastFrame - firstFrame) / framesPerTask + 1; }
};

FarmJobs readFarmJobs(const std::filesystem::path& dir);
void writeFarmJobs(const std::filesystem::path& dir, const FarmJobs& jobs);

/// The job ids (array jobs as "ID_TASK") that squeue still lists as pending or running, with
/// their state and reason; throws if squeue cannot be started.
std::map<std::string, std::string> queuedJobs(const std::vector<std::string>& ids);

}  // namespace mf::pipeline
