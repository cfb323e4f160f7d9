#include "app/child_process.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <sstream>

extern char** environ;

namespace ff::app {

namespace {

// `program` as execve needs it: itself when it names a path, else its first executable in PATH
std::string executable(const std::string& program) {
  if (program.find('/') != std::string::npos) return program;
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

}  // namespace

pid_t spawn_child(const ChildSpec& spec) {
  // everything the child needs is made before fork: after it, in a process with threads, the
  // child may only make system calls until exec
  const std::string exe = executable(spec.program);
  if (exe.empty()) {
    errno = ENOENT;
    return -1;
  }
  std::vector<std::string> args = spec.args, env = spec.env;
  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  char* const* child_env = spec.env.empty() ? environ : envp.data();
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid != 0) return pid;  // the parent (or -1, errno set by fork)
  if (prctl(PR_SET_PDEATHSIG, spec.death_signal) != 0 || getppid() != parent) _exit(127);
  const int log = open(spec.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (log < 0 || dup2(log, STDOUT_FILENO) < 0 || (spec.stderr_to_log && dup2(log, STDERR_FILENO) < 0)) _exit(127);
  execve(exe.c_str(), argv.data(), child_env);
  _exit(127);
}

}  // namespace ff::app
