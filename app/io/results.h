#pragma once
/// \file results.h
/// The HDF5 result store: results.h5 written during a run, read back for replay and plots.
/// The file layout (groups, data sets, shapes, attributes, units) is documented in
/// results_layout.md beside this header. This header does not include hdf5.h.
///
/// Crash safety: frames are staged in memory and written in blocks; every block ends with
/// H5Fflush of the data, then of `frames_written`, so a process that is killed or stops
/// without finish() leaves a file that opens and holds every frame up to the last flush.
/// Between flushes the writer does not touch the file. A kill *during* a flush can, rarely,
/// damage earlier rows (HDF5 without SWMR does not order its metadata writes); every frame
/// carries a checksum and the reader drops frames that fail it in unfinished files.

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/frame/frame.h"

namespace ff::io {

/// Why a name in `info` that outputs turn into a file name cannot be one (core/frame/file_name.h),
/// or "": the scene name (export/<name>.pvd) and every probe name (plots/<name>.png). The writer
/// refuses such a run before it writes, and the reader refuses such a file, so that a results
/// file from someone else cannot point `replay` or `compare` at a path outside --out.
std::string file_names_problem(const RunInfo& info);

/// Writes one run to an HDF5 file. Not copyable; use from one thread at a time.
class ResultWriter {
 public:
  /// Frames staged in memory before append() writes them (see flush()).
  static constexpr std::size_t kFlushFrames = 50;
  /// Wall time after which append() writes the staged frames even if fewer than kFlushFrames.
  static constexpr double kFlushSeconds = 1.0;

  /// Creates (or truncates) `path` and writes the constant run description: scene name, path
  /// and text, effects, settings, time unit, mesh, probe and field names/units/labels.
  /// Refuses (without truncating) a file that another process has open.
  /// Returns nullptr and sets *error (naming the path and the HDF5 reason) on failure,
  /// including invalid names (probe/field names must be unique, non-empty, without '/').
  static std::unique_ptr<ResultWriter> create(const std::string& path, const RunInfo& info,
                                              std::string* error);

  /// Stores `frame` (every frame is kept). Sizes must match the RunInfo: 3n points and
  /// base_points, one value per probe, one n-vector per field; otherwise nothing is stored
  /// and false is returned. Writes the staged frames to the file when kFlushFrames are staged
  /// or kFlushSeconds have passed since the last flush.
  bool append(const Frame& frame, std::string* error);

  /// Records a free-form string attribute (render backend, GL renderer, git hash, build
  /// flags ...), written at the next flush. A repeated key keeps the last value; an empty key
  /// is ignored.
  void set_attribute(const std::string& key, const std::string& value);

  /// Stores the modes of an eigen-analysis under /modes (results_layout.md): the table (number,
  /// value, eigenvalue, rigid_body) and each mode's displacement of the mesh points (n x 3),
  /// written and flushed at once. Once per file, before finish(). Returns false (nothing
  /// stored) when a displacement does not have 3 values per mesh point or it was called before.
  bool write_modes(const ModeSet& modes, std::string* error);

  /// Stores one error-bar twin's probe histories under /error_bar_twins/<twin> (results_layout.md):
  /// its description and the x of its curves (time, or the load of a static path) as attributes and
  /// datasets, one value per published frame of the twin: `time` and one per probe, by the probe's
  /// name. `twin` must be a plain name (letters, digits, '_'); each series as long as `time`.
  /// Written and flushed at once, before finish().
  bool write_twin_history(const std::string& twin, const std::string& description, const std::vector<double>& time,
                          const std::vector<std::string>& probe_names, const std::vector<std::vector<double>>& probes,
                          std::string* error);

  /// Writes the staged frames and attributes, updates `frames_written` and the provisional
  /// outcome, and calls H5Fflush. After it returns true, a killed process loses nothing.
  bool flush(std::string* error);

  /// Flushes, writes the outcome (status, reason, stop_time, steps, wall_time_s) and the
  /// metrics (name -> number, a repeated name keeps the last value), and closes the file.
  /// Any later call fails.
  bool finish(const RunOutcome& outcome,
              const std::vector<std::pair<std::string, double>>& metrics, std::string* error);

  /// Number of frames appended so far (written or staged).
  std::size_t frames_appended() const;
  /// Number of frames known to be in the file (as of the last successful flush).
  std::size_t frames_flushed() const;
  const std::string& path() const;

  /// Without finish(): flushes and closes; the file then reads as RunStatus::interrupted.
  ~ResultWriter();
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

 private:
  struct Impl;
  explicit ResultWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Rewrites the status and reason of a finished results file's outcome, when what the run did
/// after finish() (drawing frames and plots, the movie, exports, the mode pictures) changed its
/// verdict: a Ctrl-C or a full disk then, so that results.h5 and summary.json say one outcome.
/// Returns false with *error (naming the path and HDF5's reason) when the file cannot be updated.
bool amend_outcome(const std::string& path, const RunOutcome& outcome, std::string* error);

/// Reads a results file written by ResultWriter (finished, interrupted or killed).
/// Everything constant (info, outcome, metrics, attributes) is read by open(); frame data is
/// read on demand. The data accessors throw std::runtime_error if the file becomes unreadable
/// after open() (deleted, truncated); frame(i) throws std::out_of_range for i >= frame_count().
/// Const methods may be called from several threads (the HDF5 library is thread-safe).
class ResultReader {
 public:
  /// Returns nullptr and sets *error (naming the path and the reason) if the file does not
  /// exist, is not HDF5, is not a FlexFrame results file, or another process is writing it.
  /// A file whose writer did not finish is verified frame by frame (checksums), which reads
  /// the whole file once.
  static std::unique_ptr<ResultReader> open(const std::string& path, std::string* error);

  const RunInfo& info() const;
  /// Complete frames in the file (frames_written of the last flush).
  std::size_t frame_count() const;
  /// Full frame i: step, time, load factor, points, base_points, probes, fields, stats.
  Frame frame(std::size_t i) const;
  /// Reads every frame (and /steps row) once and checks it: HDF5's Fletcher32 checksum of each
  /// chunk and, where the file has them, the per-frame /frames/checksum. Returns "" when all is
  /// intact, else a message naming the file, the data set and the first damaged frame (index
  /// and time). Frames of an unfinished file were checked by open() and are not read again.
  std::string verify() const;
  /// Frame times, frame_count() values.
  std::vector<double> times() const;
  /// frame_count() values of the probe called `name`; empty if there is no such probe.
  std::vector<double> probe_series(const std::string& name) const;
  /// The Newton statistics of every frame (the convergence table), frame_count() rows.
  std::vector<StepStats> stats() const;
  /// The per-step convergence log (/steps, steps_written rows): one row per solver step even
  /// where frames were published every n-th step. Files without /steps give the frames' stats.
  std::vector<StepRecord> step_log() const;
  /// A file whose writer never finished reads as RunStatus::interrupted with reason
  /// "the writer did not finish (process stopped?); N frames were saved".
  RunOutcome outcome() const;
  std::vector<std::pair<std::string, double>> metrics() const;
  std::vector<std::pair<std::string, std::string>> attributes() const;
  /// The modes stored by ResultWriter::write_modes, null when the file has none.
  const ModeSet* modes() const;
  const std::string& path() const;

  ~ResultReader();
  ResultReader(const ResultReader&) = delete;
  ResultReader& operator=(const ResultReader&) = delete;

 private:
  struct Impl;
  explicit ResultReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ff::io
