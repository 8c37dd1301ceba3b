#include "pipeline/farm.h"

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "pipeline/process.h"
#include "sim/file_util.h"

namespace fs = std::filesystem;

namespace mf::pipeline {

namespace {

// The scripts are constant text: what varies arrives as arguments ("$1", "$@"), so no run folder,
// scene or option value is ever parsed by the shell that runs them.
constexpr const char* kSimScript = R"SH(#!/bin/bash
# multifluid farm: the simulation, one job (written by `multifluid farm submit`).
# Arguments: MULTIFLUID, then the arguments of `multifluid sim`; none is ever part of this text.
# Submitted with --requeue and --signal=B:USR1@S: near the time limit Slurm sends USR1 to this
# script, which passes it on; multifluid stops at the next step (the checkpoint of the last
# finished frame is intact: one is written every frame) and the job requeues itself. Preemption
# and `scontrol requeue` send SIGTERM to multifluid directly, with the same effect. A requeued
# job resumes from the checkpoint, bit for bit.
set -u
mf=$1
shift
stop=0
trap 'stop=1; kill -USR1 "$pid" 2>/dev/null' USR1
echo "multifluid farm: sim job ${SLURM_JOB_ID:-?}, start ${SLURM_RESTART_COUNT:-0}, on $(hostname)"
"$mf" "$@" &
pid=$!
# A trap ends `wait` early: wait again until multifluid itself has ended.
while wait "$pid"; status=$?; [ "$status" -gt 128 ] && kill -0 "$pid" 2>/dev/null; do :; done
if [ "$stop" = 1 ] && [ "$status" -ne 0 ]; then
  echo "multifluid farm: time limit near; stopped at a checkpoint; requeueing job $SLURM_JOB_ID"
  scontrol requeue "$SLURM_JOB_ID" && sleep 60
fi
echo "multifluid farm: exit status $status"
exit "$status"
)SH";

constexpr const char* kTaskScript = R"SH(#!/bin/bash
# multifluid farm: one task of a job array (surfacing, rendering) or the encoding job (written by
# `multifluid farm submit`). Arguments: MULTIFLUID FIRST LAST PER SIMJOB, then the arguments of
# the multifluid stage command; none is ever part of this text. Task T does frames FIRST + T*PER
# onwards, PER of them, up to LAST. SIMJOB: the simulation's job id, or 0 when none was submitted.
set -u
mf=$1 first=$2 last=$3 per=$4 simjob=$5
shift 5
task=${SLURM_ARRAY_TASK_ID:-0}
for n in "$first" "$last" "$per" "$task" "$simjob"; do
  # Digits only, no leading zero: bash arithmetic would evaluate anything else.
  if ! [[ $n =~ ^(0|[1-9][0-9]{0,6})$ ]]; then
    echo "multifluid farm: not a frame number: '$n'"
    echo "multifluid farm: exit status 2"
    exit 2
  fi
done
a=$((first + task * per))
b=$((a + per - 1))
[ "$b" -le "$last" ] || b=$last
echo "multifluid farm: $1 task $task, frames $a-$b, job ${SLURM_JOB_ID:-?} on $(hostname)"
"$mf" "$@" --frames "$a-$b"
status=$?
# 75: an input frame was still missing after --wait-for-input (the simulation is behind, or was
# requeued). Give the CPUs back and wait in the queue instead: as long as the simulation job is
# queued or running; once it has ended (or without one) only while this task has started fewer
# than 3 times, since the frame will not come.
starts=${SLURM_RESTART_COUNT:-0}
if [ "$status" -eq 75 ] && [ -n "${SLURM_JOB_ID:-}" ]; then
  sim_state=
  [ "$simjob" = 0 ] || sim_state=$(squeue --noheader --jobs "$simjob" --format %T 2> /dev/null)
  if [ -n "$sim_state" ] || [ "$starts" -lt 3 ]; then
    # An array task by ARRAYID_TASK: the array's own id would requeue every task.
    self=$SLURM_JOB_ID
    [ -z "${SLURM_ARRAY_TASK_ID:-}" ] || self="${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}"
    echo "multifluid farm: input not ready; requeueing task $self to free its CPUs (start $starts; simulation ${sim_state:-not queued})"
    scontrol requeue "$self" && sleep 60
  fi
fi
echo "multifluid farm: exit status $status"
exit "$status"
)SH";

/// One argument as a POSIX shell word, for printing command lines a user can paste.
std::string shellQuote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-.,/:=@%+") == std::string::npos)
    return s;
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string joinIds(const FarmJobs& jobs) {
  std::string ids;
  for (const auto& [stage, id] : jobs.jobs) ids += (ids.empty() ? "" : ",") + id;
  return ids;
}

std::string executablePath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the running multifluid (/proc/self/exe): " + ec.message());
  return self.string();
}

}  // namespace

int parseSlurmTime(const std::string& t) {
  if (t.empty() || t.size() > 16 || t.find_first_not_of("0123456789-:") != std::string::npos) return -1;
  std::vector<long> parts;
  long days = 0;
  std::string rest = t;
  const size_t dash = t.find('-');
  if (dash != std::string::npos) {
    const std::string d = t.substr(0, dash);
    if (d.empty() || d.find(':') != std::string::npos) return -1;
    days = std::stol(d);
    rest = t.substr(dash + 1);
  }
  std::stringstream ss(rest);
  for (std::string p; std::getline(ss, p, ':');) {
    if (p.empty() || p.find('-') != std::string::npos) return -1;
    parts.push_back(std::stol(p));
  }
  if (parts.empty() || parts.size() > 3 || rest.back() == ':') return -1;
  long s = 0;
  if (dash != std::string::npos) {  // D-H, D-H:M, D-H:M:S
    s = parts[0] * 3600 + (parts.size() > 1 ? parts[1] * 60 : 0) + (parts.size() > 2 ? parts[2] : 0);
  } else if (parts.size() == 1) {  // M
    s = parts[0] * 60;
  } else if (parts.size() == 2) {  // M:S
    s = parts[0] * 60 + parts[1];
  } else {  // H:M:S
    s = parts[0] * 3600 + parts[1] * 60 + parts[2];
  }
  s += days * 86400;
  return s > 0 && s < (1L << 31) ? int(s) : -1;
}

FarmJobs readFarmJobs(const fs::path& dir) {
  const fs::path file = dir / "farm" / "jobs.txt";
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read (was `multifluid farm submit` run with this --out?)");
  FarmJobs j;
  std::string line;
  if (!std::getline(in, line) || line != "multifluid farm jobs 1") throw std::runtime_error(file.string() + ": not a farm jobs file");
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "scene") ls >> j.scene;
    else if (key == "frames") ls >> j.firstFrame >> j.lastFrame;
    else if (key == "frames_per_task") ls >> j.framesPerTask;
    else if (key == "job") {
      std::string stage, id;
      if (ls >> stage >> id) j.jobs.push_back({stage, id});
    }
    if (!ls && !ls.eof()) throw std::runtime_error(file.string() + ": malformed line '" + line + "'");
  }
  if (j.framesPerTask < 1 || j.lastFrame < j.firstFrame) throw std::runtime_error(file.string() + ": bad frame range");
  return j;
}

void writeFarmJobs(const fs::path& dir, const FarmJobs& j) {
  std::string text = fmt::format("multifluid farm jobs 1\nscene {}\nframes {} {}\nframes_per_task {}\n", j.scene, j.firstFrame,
                                 j.lastFrame, j.framesPerTask);
  for (const auto& [stage, id] : j.jobs) text += fmt::format("job {} {}\n", stage, id);
  writeFileAtomically((dir / "farm" / "jobs.txt").string(), text);
}

std::map<std::string, std::string> queuedJobs(const std::vector<std::string>& ids) {
  std::map<std::string, std::string> q;
  if (ids.empty()) return q;
  std::string list;
  for (const auto& id : ids) list += (list.empty() ? "" : ",") + id;
  const ProgramOutput r = captureProgram({"squeue", "--noheader", "--array", "--jobs", list, "--format", "%i|%T|%r"});
  // squeue refuses a list whose jobs have all left the controller: then none is queued.
  if (r.status != 0) {
    if (r.err.find("Invalid job id") != std::string::npos) return q;
    throw std::runtime_error("squeue failed: " + r.err);
  }
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    const size_t bar = line.find('|');
    if (bar != std::string::npos) q[line.substr(0, bar)] = line.substr(bar + 1);
  }
  return q;
}

int farmSubmit(const Scene& scene, const FarmSubmitOptions& o) {
  const fs::path& out = o.out;
  const fs::path farm = out / "farm";
  fs::create_directories(farm / "logs");
  // A second submission into a folder whose jobs still run would race with them.
  if (fs::exists(farm / "jobs.txt") && !o.dryRun) {
    const FarmJobs old = readFarmJobs(out);
    std::vector<std::string> ids;
    for (const auto& [stage, id] : old.jobs) ids.push_back(id);
    if (const auto q = queuedJobs(ids); !q.empty())
      throw std::runtime_error(fmt::format("{} has farm jobs still queued or running ({}); wait for them, or `multifluid farm "
                                           "cancel` the folder first",
                                           out.string(), joinIds(old)));
  }
  const fs::path sceneCopy = farm / "scene.toml";
  writeFileAtomically(sceneCopy.string(), scene.sourceText);
  writeFileAtomically((farm / "sim.sbatch").string(), kSimScript);
  writeFileAtomically((farm / "task.sbatch").string(), kTaskScript);

  const std::string mf = executablePath();
  const std::string frames = fmt::format("{}-{}", o.firstFrame, o.lastFrame);
  const int tasks = (o.lastFrame - o.firstFrame) / o.framesPerTask + 1;
  auto has = [&](const char* s) { return std::find(o.stages.begin(), o.stages.end(), s) != o.stages.end(); };
  auto common = [&](const std::string& stage, bool array) {
    std::vector<std::string> a = {"sbatch", "--parsable", "--job-name=mf-" + stage + "-" + scene.name, "--chdir=" + out.string(),
                                  array ? "--output=farm/logs/" + stage + "-%A_%a.log" : "--output=farm/logs/" + stage + "-%j.log",
                                  "--open-mode=append", "--requeue", fmt::format("--cpus-per-task={}", o.cpusPerTask)};
    if (!o.partition.empty()) a.push_back("--partition=" + o.partition);
    if (!o.timeLimit.empty()) a.push_back("--time=" + o.timeLimit);
    if (array) a.push_back(fmt::format("--array=0-{}", tasks - 1));
    // A job whose dependency failed leaves the queue instead of pending for ever.
    if (stage != "sim") a.push_back("--kill-on-invalid-dep=yes");
    return a;
  };
  auto stageArgs = [&](const std::string& stage) {
    std::vector<std::string> a = {stage, sceneCopy.string(), "--out", out.string()};
    if (stage != "encode") a.insert(a.end(), {"--threads", std::to_string(o.cpusPerTask)});
    if (stage == "surface" || stage == "render") a.insert(a.end(), {"--wait-for-input", fmt::format("{}", o.waitForInputSeconds)});
    a.insert(a.end(), o.passOptions.begin(), o.passOptions.end());
    return a;
  };

  FarmJobs jobs{scene.name, o.firstFrame, o.lastFrame, o.framesPerTask, {}};
  std::string previous;  // the job the next one depends on
  std::string simJob;    // the tasks ask Slurm whether it still runs; "" when not submitted
  auto submit = [&](const std::string& stage, std::vector<std::string> argv) {
    if (o.dryRun) {
      std::string line;
      for (const auto& a : argv) line += (line.empty() ? "" : " ") + shellQuote(a);
      fmt::print("{}\n", line);
      previous = "<" + stage + " job id>";
      jobs.jobs.push_back({stage, previous});
      return;
    }
    const ProgramOutput r = captureProgram(argv);
    std::string id = r.out.substr(0, r.out.find_first_of(";\n"));
    if (r.status != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
      // Nothing half-submitted stays behind: the jobs already queued are cancelled.
      std::vector<std::string> cancel = {"scancel"};
      for (const auto& [submitted, id] : jobs.jobs) cancel.push_back(id);
      if (cancel.size() > 1) captureProgram(cancel);
      throw std::runtime_error(fmt::format("sbatch failed for the {} job (status {}): {}{}", stage, r.status, r.err,
                                           jobs.jobs.empty() ? "" : fmt::format(" (cancelled jobs {})", joinIds(jobs))));
    }
    jobs.jobs.push_back({stage, id});
    previous = id;
    fmt::print("submitted {} job {}\n", stage, id);
  };
  auto withArgs = [](std::vector<std::string> a, const std::string& script, const std::vector<std::string>& args) {
    a.push_back(script);
    a.insert(a.end(), args.begin(), args.end());
    return a;
  };
  const std::string taskScript = (farm / "task.sbatch").string();
  auto sliceArgs = [&](int per) {
    return std::vector<std::string>{mf, std::to_string(o.firstFrame), std::to_string(o.lastFrame), std::to_string(per),
                                    simJob.empty() ? "0" : simJob};
  };

  if (has("sim")) {
    // USR1 a while before the limit: one step is enough to stop, as a checkpoint exists per frame.
    const int before = o.timeLimitSeconds > 0 ? std::clamp(o.timeLimitSeconds / 5, 5, 120) : 120;
    auto a = common("sim", false);
    a.push_back(fmt::format("--signal=B:USR1@{}", before));
    std::vector<std::string> args = {mf};
    for (const auto& s : stageArgs("sim")) args.push_back(s);
    args.insert(args.end(), {"--frames", frames});
    submit("sim", withArgs(a, (farm / "sim.sbatch").string(), args));
  }
  simJob = previous;
  std::string surfaceJob;
  if (has("surface")) {
    auto a = common("surface", true);
    if (!previous.empty()) a.push_back("--dependency=after:" + previous);  // start once the sim runs
    auto args = sliceArgs(o.framesPerTask);
    for (const auto& s : stageArgs("surface")) args.push_back(s);
    submit("surface", withArgs(a, taskScript, args));
    surfaceJob = previous;
  }
  if (has("render")) {
    auto a = common("render", true);
    if (!surfaceJob.empty()) a.push_back("--dependency=aftercorr:" + surfaceJob);  // task i after surfacing task i
    else if (!previous.empty()) a.push_back("--dependency=after:" + previous);
    auto args = sliceArgs(o.framesPerTask);
    for (const auto& s : stageArgs("render")) args.push_back(s);
    submit("render", withArgs(a, taskScript, args));
  }
  if (has("encode")) {
    auto a = common("encode", false);
    if (!previous.empty()) a.push_back("--dependency=afterok:" + previous);
    auto args = sliceArgs(o.lastFrame - o.firstFrame + 1);
    for (const auto& s : stageArgs("encode")) args.push_back(s);
    submit("encode", withArgs(a, taskScript, args));
  }
  if (o.dryRun) {
    fmt::print("dry run: scripts written to {}; nothing submitted\n", farm.string());
    return 0;
  }
  writeFarmJobs(out, jobs);
  fmt::print("{} frames {} in {} task(s) per stage; jobs recorded in {}; `multifluid farm status {}`\n", scene.name, frames, tasks,
             (farm / "jobs.txt").string(), shellQuote(out.string()));
  return 0;
}

int farmCancel(const fs::path& dir) {
  const FarmJobs jobs = readFarmJobs(dir);
  std::vector<std::string> ids;
  for (const auto& [stage, id] : jobs.jobs) ids.push_back(id);
  // Only jobs still queued: scancel fails on those that have left the controller.
  std::set<std::string> queued;
  for (const auto& [key, state] : queuedJobs(ids)) queued.insert(key.substr(0, key.find('_')));
  std::vector<std::string> argv = {"scancel"};
  for (const auto& id : ids)
    if (queued.count(id)) argv.push_back(id);
  if (argv.size() == 1) {
    fmt::print("no job of {} is queued or running (jobs {})\n", dir.string(), joinIds(jobs));
    return 0;
  }
  const ProgramOutput r = captureProgram(argv);
  if (r.status != 0) {
    fmt::print(stderr, "scancel failed (status {}): {}", r.status, r.err);
    return r.status;
  }
  std::vector<std::string> cancelled(argv.begin() + 1, argv.end());
  fmt::print("cancelled jobs {} of {}\n", fmt::join(cancelled, ","), dir.string());
  return 0;
}

}  // namespace mf::pipeline
