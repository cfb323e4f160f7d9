#pragma once
/// \file child_process.h
/// Processes the app starts and waits for (a study's variant runs, `bench --ranks`'s launches)
/// die with it: a flexframe ended by SIGKILL (a batch system's hard stop, the OOM killer,
/// `kill -9`) must not leave children running unattended, writing into its output folder for
/// hours. (The Gmsh child of app/io/gmsh_import.cpp, which is not a program of its own, does the
/// same in its own way.)

#include <sys/types.h>

#include <csignal>

#include <string>
#include <vector>

namespace ff::app {

struct ChildSpec {
  std::string program;             ///< a path, or a name looked up in PATH
  std::vector<std::string> args;   ///< argv, args[0] included
  std::vector<std::string> env;    ///< the environment ("NAME=value"); empty: this process's
  std::string log;                 ///< stdout goes to this file (created or truncated; not through a link)
  bool stderr_to_log = false;      ///< stderr too (else it stays this process's)
  /// Sent to the child when this process dies (PR_SET_PDEATHSIG; kept across exec). SIGTERM lets
  /// a flexframe child end as `interrupted` with its records written, and makes mpirun stop its ranks.
  int death_signal = SIGTERM;
};

/// Starts the child (fork, then exec); its pid, or -1 with errno set. The death signal comes when
/// the thread that called this ends, so call it from the thread that waits for the child. A child
/// whose parent died before the signal was set ends at once (exit code 127).
pid_t spawn_child(const ChildSpec& spec);

}  // namespace ff::app
