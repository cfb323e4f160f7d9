#pragma once
#include <string>
#include <vector>
namespace ff::app {
/// `flexframe compare`: overlay plots of the probes of several stored runs. Returns an exit code.
int compare_runs(const std::vector<std::string>& inputs, const std::string& out_dir);
}  // namespace ff::app
