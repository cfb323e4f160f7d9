#pragma once
/// `flexframe policies`: Tables 3-4 of the shell paper (Zhang, Liu, Zhang & Liu 2022) for any
/// shell scene of the dynamic analysis -- Newton iterations (NOI) and iteration-matrix updates (NOU) for each
/// matrix policy and step size, with wall time.
#include <atomic>
#include <string>
#include <vector>

namespace ff::app {

struct PolicyTableOptions {
  std::string scene = "double_pendulum_shells";
  std::vector<std::string> dts = {"5e-4"};                       ///< time steps [s]
  std::vector<std::string> policies = {"full", "nni:2", "nni:3", "nni:4", "frozen"};
  double until = 1.0;                                             ///< simulated time per run [s]
  std::vector<std::string> overrides;                             ///< extra --set for every run
  std::string out_dir = "out/policies";
};

/// Writes policies.csv, policies.md and policies.png; prints the markdown table.
int run_policy_table(const PolicyTableOptions& options, const std::atomic<bool>& stop);

}  // namespace ff::app
