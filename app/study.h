#pragma once
#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "app/study_spec.h"

namespace ff::app {

/// `flexframe study` as given on the command line.
struct StudyOptions {
  std::string target;                  ///< bundled study name, study file, or scene (name or file)
  std::vector<std::string> vary;       ///< "KEY[+KEY2]=V1,V2,..."; added to a study file's axes
  std::vector<std::string> overrides;  ///< --set on every run
  std::string metric;                  ///< overrides the study file's
  std::string reference;               ///< "finest", a number, "scene:NAME"; "" = the file's / finest
  std::string baseline;                ///< legacy: same as --reference scene:BASELINE
  bool each = false;                   ///< vary one axis at a time instead of the grid
  std::optional<int> repeat;
  std::string out_dir;                 ///< "" = out/study/<study name>
  bool check_only = false;             ///< validate every variant's scene, run nothing
};

/// Builds the study from a study file and/or the options; throws InputError / SceneError.
StudySpec make_study_spec(const StudyOptions& options);

/// `flexframe study`: what accuracy costs. Runs every variant in sequence (each on a worker
/// thread, repetitions interleaved so machine drift spreads over all variants) and writes
/// study.csv, study.md and pareto.png (error against wall time, log-log, with the Pareto front).
/// Returns the exit code.
int run_study(const StudySpec& spec, const std::string& out_dir, const std::atomic<bool>& stop);

/// Checks that every variant (and the reference run) builds; prints one line per variant.
/// Throws SceneError naming the variant on the first bad one.
int check_study(const StudySpec& spec);

}  // namespace ff::app
