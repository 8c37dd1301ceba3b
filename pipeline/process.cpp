#include "pipeline/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace mf::pipeline {

std::string findOnPath(const std::string& program) {
  if (program.empty() || program.find('/') != std::string::npos) return {};
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (dir.empty()) continue;  // an empty entry would mean the current folder: never searched
    const std::string candidate = dir + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

namespace {
struct FileActions {
  posix_spawn_file_actions_t actions;
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
};
}  // namespace

int runProgram(const std::vector<std::string>& argv, const SpawnOptions& options) {
  if (argv.empty()) throw std::runtime_error("runProgram: no program given");
  const std::string program = findOnPath(argv[0]);
  if (program.empty()) throw std::runtime_error(argv[0] + " was not found on PATH");
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  FileActions fa;
  int rc = posix_spawn_file_actions_addopen(&fa.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (rc == 0 && !options.stdoutFile.empty())
    rc = posix_spawn_file_actions_addopen(&fa.actions, STDOUT_FILENO, options.stdoutFile.c_str(),
                                          O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (rc == 0 && !options.stderrFile.empty())
    rc = posix_spawn_file_actions_addopen(&fa.actions, STDERR_FILENO, options.stderrFile.c_str(),
                                          O_WRONLY | O_CREAT | O_TRUNC, 0644);
  // File actions run in order in the child, so the output files above are relative to the
  // caller's folder; the program itself then runs in the working directory.
  if (rc == 0 && !options.workingDirectory.empty())
    rc = posix_spawn_file_actions_addchdir_np(&fa.actions, options.workingDirectory.c_str());
  if (rc != 0) throw std::runtime_error("cannot prepare to start " + argv[0] + ": " + std::strerror(rc));

  pid_t pid = 0;
  rc = posix_spawn(&pid, program.c_str(), &fa.actions, nullptr, args.data(), environ);
  if (rc != 0) throw std::runtime_error("cannot start " + program + ": " + std::strerror(rc));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waiting for " + program + ": " + std::strerror(errno));
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 255;
}

}  // namespace mf::pipeline
