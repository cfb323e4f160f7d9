// flexframe: command-line entry point. The verbs, their options and how they run are in
// app/command_line.h; this file is the process around them.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <string>

#include "app/command_line.h"
#include "app/io/machine_memory.h"

namespace {
std::atomic<bool> g_stop{false};
std::atomic<int> g_stop_signal{0};  // the first signal that set g_stop (run: the outcome names SIGTERM)

extern "C" void on_sigint(int signo) {
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, signo);
  if (g_stop.exchange(true)) {  // second Ctrl-C: leave at once
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
  }
}
}  // namespace

int main(int argc, char** argv) {
  ff::app::CommandLine command_line;
  if (const std::optional<int> code = command_line.parse(argc, argv)) return *code;
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  // a memory limit that cannot be read would otherwise be ignored without a word
  if (std::string memory_error; ff::io::machine_memory_limit_bytes(&memory_error), !memory_error.empty()) {
    std::fprintf(stderr, "error: %s\n", memory_error.c_str());
    return 2;
  }

  return command_line.run(g_stop, g_stop_signal);
}
