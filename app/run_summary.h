#pragma once
/// \file run_summary.h
/// summary.json of a run: what scripts and benchmarks read, keys in a fixed order (NaN is
/// written as null). The full one at the end of a run, and the short ones written when a run
/// ends before it has metrics (results.h5 could not be made; the MPI launcher stopped it).

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

#include "app/mode_outputs.h"
#include "app/output_folder.h"
#include "app/output_pipeline.h"
#include "app/run_result.h"
#include "core/scene/scene.h"

namespace ff::app {

/// Everything the full summary reports, gathered by the run once every output is written.
struct RunSummaryInputs {
  const scene::LoadedScene* scene = nullptr;  ///< name, path, mesh quality
  const RunInfo* info = nullptr;
  const RunResult* result = nullptr;          ///< its outcome is the one reported
  std::vector<std::pair<std::string, std::string>> metrics_unreached;  ///< name, why
  std::vector<EffectStat> effect_stats;
  const OutputPipeline* pipeline = nullptr;   ///< frames, plots, render backend, stress peak
  std::vector<std::string> plot_files;        ///< the pipeline's plots and the mode spectrum
  const ModeSet* modes = nullptr;             ///< an eigen-analysis's modes, or null
  const ModeOutputReport* mode_report = nullptr;
  std::string color_field;                    ///< output.color_field
};

nlohmann::ordered_json run_summary(const RunSummaryInputs& in);

/// A run that ends `failed` before its first frame: results.h5 could not be created.
nlohmann::ordered_json summary_before_any_frame(const std::string& scene_name, const std::string& scene_path,
                                                const std::string& reason);
/// A run the MPI launcher stopped while its solver is blocked (launcher_watchdog.h): the outcome
/// without the metrics, which the blocked solver thread holds.
nlohmann::ordered_json summary_without_metrics(const std::string& scene_name, const std::string& scene_path,
                                               const RunOutcome& outcome, const std::string& time_unit);

/// Writes `summary` as folder/summary.json (2-space indent). Throws WriteError.
void write_summary(OutputFolder& folder, const nlohmann::ordered_json& summary);

}  // namespace ff::app
