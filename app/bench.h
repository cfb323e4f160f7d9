#pragma once
#include <atomic>
#include <string>
namespace ff::app {
struct BenchOptions {
  int repeat = 5;
  std::string out_file;  ///< optional JSON
};
/// `flexframe bench`: steps/s of every bundled hub-beam scene, EFG/FEM cost ratios and headless
/// frames/s, as a markdown table. Ratios come from one run of this command.
int run_bench(const BenchOptions& options, const std::atomic<bool>& stop);
}  // namespace ff::app
