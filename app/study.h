#pragma once
#include <atomic>
#include <string>
#include <vector>
namespace ff::app {
struct StudyOptions {
  std::string scene;
  std::vector<std::string> vary;  ///< "key=v1,v2,..."; each varied alone
  std::string baseline;           ///< scene defining relative time and the reference value ("" = first variant)
  std::string metric;             ///< summary metric compared with the reference
  int repeat = 5;
  std::string out_dir = "out/study";
};
/// `flexframe study`: what accuracy costs in time. Writes study.csv, study.md and study.png.
int run_study(const StudyOptions& options, const std::atomic<bool>& stop);
}  // namespace ff::app
