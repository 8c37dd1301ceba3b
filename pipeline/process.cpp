#include "pipeline/process.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <thread>

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
/// The exit status of a started program; killed by signal N: 128 + N.
int waitFor(pid_t pid, const std::string& program) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error("waiting for " + program + ": " + std::strerror(errno));
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 255;
}

/// waitFor with a limit: a program still running after `seconds` is sent SIGTERM, then SIGKILL
/// if it has not exited 5 s later, reaped, and reported as an error (a hung child never hangs us).
int waitFor(pid_t pid, const std::string& program, double seconds) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  int status = 0;
  bool termSent = false;
  for (;;) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) throw std::runtime_error("waiting for " + program + ": " + std::strerror(errno));
    if (!termSent && elapsed() > seconds) {
      ::kill(pid, SIGTERM);
      termSent = true;
    } else if (termSent && elapsed() > seconds + 5) {
      ::kill(pid, SIGKILL);
      waitFor(pid, program);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (termSent)
    throw std::runtime_error(program + " was stopped after running past its time limit of " + std::to_string(int(seconds)) + " s");
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 255;
}

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
  return options.timeoutSeconds > 0 ? waitFor(pid, program, options.timeoutSeconds) : waitFor(pid, program);
}

ProgramOutput captureProgram(const std::vector<std::string>& argv) {
  if (argv.empty()) throw std::runtime_error("captureProgram: no program given");
  const std::string program = findOnPath(argv[0]);
  if (program.empty()) throw std::runtime_error(argv[0] + " was not found on PATH");
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int outPipe[2], errPipe[2];
  if (::pipe2(outPipe, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  if (::pipe2(errPipe, O_CLOEXEC) != 0) {
    ::close(outPipe[0]), ::close(outPipe[1]);
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  }
  FileActions fa;
  posix_spawn_file_actions_addopen(&fa.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&fa.actions, outPipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&fa.actions, errPipe[1], STDERR_FILENO);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, program.c_str(), &fa.actions, nullptr, args.data(), environ);
  ::close(outPipe[1]), ::close(errPipe[1]);
  if (rc != 0) {
    ::close(outPipe[0]), ::close(errPipe[0]);
    throw std::runtime_error("cannot start " + program + ": " + std::strerror(rc));
  }
  // Both pipes are drained together, so that neither can fill up and block the program.
  ProgramOutput result;
  pollfd fds[2] = {{outPipe[0], POLLIN, 0}, {errPipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&result.out, &result.err};
  int open = 2;
  char buf[4096];
  while (open > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        sinks[i]->append(buf, size_t(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open;
      }
    }
  }
  for (const pollfd& p : fds)
    if (p.fd >= 0) ::close(p.fd);
  result.status = waitFor(pid, program);
  return result;
}

}  // namespace mf::pipeline
