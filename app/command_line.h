#pragma once
/// \file command_line.h
/// The verbs of `flexframe` (run, replay, check, scenes, compare, bench, study, policies, gui),
/// their options, and how the chosen one runs: alone, or with one model or a study's variants
/// over the MPI ranks it was launched on, every error turned into its exit code (README.md).
/// main.cpp is only the process around it: the signals and the machine's memory limit.

#include <atomic>
#include <memory>
#include <optional>

namespace ff::app {

class CommandLine {
 public:
  CommandLine();  ///< every verb and its options
  ~CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  /// Reads argv. An exit code to end with at once (--help: 0; a usage error: 2, said), or none.
  std::optional<int> parse(int argc, char** argv);
  /// Runs the verb parsed and returns the process's exit code. `interrupt` is set by Ctrl-C or
  /// SIGTERM (`interrupt_signal` says which); over MPI ranks rank 0's stop reaches every rank.
  int run(std::atomic<bool>& interrupt, const std::atomic<int>& interrupt_signal);

 private:
  struct Verbs;
  std::unique_ptr<Verbs> verbs_;
};

}  // namespace ff::app
