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
  int jobs = 0;                        ///< variants at a time; 0 = the machine's cores
  bool exclusive_timing = false;       ///< --timing exclusive: timed repetitions one at a time
  bool resume = false;                 ///< skip variants whose run folder is complete
};

/// The hidden `flexframe study-variant`: one variant in a child process of `study --jobs N`.
struct StudyVariantOptions {
  std::string scene;                   ///< resolved scene path
  std::vector<std::string> overrides;
  int reps = 1;                        ///< timing repetitions (the first gives the metrics)
  std::string result;                  ///< summary.json to write (not written when stopped)
  bool shared = false;                 ///< recorded: other variants ran at the same time
};

/// Builds the study from a study file and/or the options; throws InputError / SceneError.
StudySpec make_study_spec(const StudyOptions& options);

/// `flexframe study`: what accuracy costs. With jobs 1 runs every variant in sequence in this
/// process (each on a worker thread, repetitions interleaved so machine drift spreads over all
/// variants); with jobs > 1 runs up to `jobs` variants at once as single-threaded child processes
/// of this binary (timing then marked shared; exclusive_timing re-times them one at a time).
/// Every variant's result goes to <out>/runs/NNN/summary.json (what resume reads back), then
/// study.csv, study.md and pareto.png (error against wall time, log-log, with the Pareto front).
/// Returns the exit code.
int run_study(const StudySpec& spec, const StudyOptions& options, const std::atomic<bool>& stop);

/// `flexframe study-variant`: runs one variant and writes its summary.json; returns the exit code.
int run_study_variant(const StudyVariantOptions& options, const std::atomic<bool>& stop);

/// Checks that every variant (and the reference run) builds; prints one line per variant.
/// Throws SceneError naming the variant on the first bad one.
int check_study(const StudySpec& spec);

}  // namespace ff::app
