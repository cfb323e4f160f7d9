#pragma once
/// \file results_names.h
/// Names of the groups, data sets and attributes of results.h5, shared by writer and reader.
/// results_layout.md documents them for users; change both together (and kFormatVersion).

#include <cstdint>

namespace ff::io::names {

inline constexpr const char* kFormat = "flexframe-results";  ///< root attribute "format"
inline constexpr std::int64_t kFormatVersion = 1;            ///< root attribute "format_version"

inline constexpr const char* kRun = "/run";
inline constexpr const char* kSettings = "/run/settings";
inline constexpr const char* kSceneText = "/run/scene_text";
inline constexpr const char* kMesh = "/mesh";
inline constexpr const char* kFrames = "/frames";
inline constexpr const char* kStats = "/frames/stats";
inline constexpr const char* kProbes = "/frames/probes";
inline constexpr const char* kFields = "/frames/fields";
inline constexpr const char* kOutcome = "/outcome";
inline constexpr const char* kMetrics = "/metrics";
inline constexpr const char* kAttributes = "/attributes";

inline constexpr const char* kFramesWritten = "frames_written";
inline constexpr const char* kSteps = "/steps";  ///< the per-step convergence log
inline constexpr const char* kStepsWritten = "steps_written";
inline constexpr const char* kModes = "/modes";  ///< an eigen-analysis' modes (issue 36)
inline constexpr const char* kErrorBarTwins = "/error_bar_twins";  ///< the error-bar twins' probe histories (issue 49)

/// Reason stored (and reported by the reader) while the writer has not finished.
inline constexpr const char* kUnfinished = "the writer did not finish (process stopped?)";

}  // namespace ff::io::names
