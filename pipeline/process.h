// Starting external programs (ffmpeg, gnuplot, Slurm's commands) without a shell: an argument vector goes straight
// to posix_spawn, so no text from a scene or the command line is ever interpreted by a shell.
#pragma once

#include <string>
#include <vector>

namespace mf::pipeline {

/// The full path of `program` found on PATH (executable regular file), or "" if there is none.
std::string findOnPath(const std::string& program);

struct SpawnOptions {
  std::string workingDirectory;  // "" = the current one
  std::string stdoutFile;        // "" = inherited; else truncated and written
  std::string stderrFile;        // "" = inherited; else truncated and written
  double timeoutSeconds = 0;     // > 0: past it the program gets SIGTERM (SIGKILL 5 s later), and runProgram throws
};

/// Runs argv[0] (looked up on PATH) with the arguments as given, standard input from /dev/null,
/// and waits for it. Returns its exit status; a program killed by signal N returns 128 + N.
/// Throws std::runtime_error if it cannot be started, or if it ran past options.timeoutSeconds.
int runProgram(const std::vector<std::string>& argv, const SpawnOptions& options = {});

struct ProgramOutput {
  int status = 0;
  std::string out, err;
};

/// Like runProgram, but returns what the program wrote to its standard output and error (for
/// Slurm's sbatch, squeue, sacct, scancel).
ProgramOutput captureProgram(const std::vector<std::string>& argv);

}  // namespace mf::pipeline
