#pragma once
/// \file output_folder.h
/// An output folder that one flexframe job owns while it writes: the only place a run, replay
/// or study writes to, and the only place it deletes from.
///
/// Four rules keep a user's files safe (docs/guide/running.md, "What a run may touch"):
/// - the folder's lock (`.flexframe.lock`, an flock) is taken before any other file in it is
///   touched, so a second job on the same folder is refused before it changes anything;
/// - a job deletes only files that an earlier flexframe job recorded in the folder's manifest
///   (`.flexframe-files`, one relative path a line), never a whole tree, and never through a
///   symbolic link;
/// - every file a job writes is recorded in the manifest (a file missing from it is only ever
///   kept, never deleted);
/// - nothing is written through a link: the folders on the way to an output must be real folders
///   this user owns (`file`, `sub_folder`), and the output itself absent or a regular file with no
///   other name; every writer flexframe owns opens it with core/frame/output_file.h, which refuses a
///   link, a FIFO or a device at the last step too. A planted link is refused, never followed and
///   never deleted.
/// And one rule keeps the record true on a full disk: the folder holds a reserve of
/// kReserveBytes (`.flexframe-reserve`, allocated when the folder is claimed) that is given back
/// the moment a write fails, so that the outcome (results.h5's status, summary.json) can still
/// be written after the disk has filled up.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>

namespace ff::app {

/// A write that did not reach the disk. `what()` names the file and the reason; a full disk
/// or quota says "disk full".
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// "disk full" for ENOSPC and EDQUOT, else strerror(err): the words a failed write is reported with.
std::string write_failure_reason(int err);

/// Writes `text` to `path` through a temporary file renamed over it, checking every step
/// (open, write, flush, close, rename). The temporary `<path>.tmp` is opened without following a
/// link (core/frame/output_file.h). Throws WriteError naming `path` on failure and leaves no
/// temporary behind.
void write_text_file(const std::filesystem::path& path, const std::string& text);

class OutputFolder {
 public:
  /// Creates `dir` (and its parents) when missing and takes its lock. Throws WriteError when
  /// the folder cannot be created or the lock file written, and std::runtime_error naming the
  /// other job (its verb and pid) when one holds the lock. `job` names this one ("run", ...).
  OutputFolder(const std::filesystem::path& dir, const std::string& job);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// Room kept for the final records; a folder with less free space is refused when claimed.
  static constexpr std::size_t kReserveBytes = 256 * 1024;

  const std::filesystem::path& path() const { return dir_; }

  /// Gives the reserve back to the file system (once; thread-safe): called when a write failed.
  void release_reserve();

  /// Records `relative` (a file or, with a trailing '/', a folder, inside this folder) in the
  /// manifest. Throws WriteError when the manifest cannot be written; thread-safe.
  void record(const std::string& relative);
  /// record() then the path inside the folder, for the writer to create. Throws WriteError when a
  /// folder on the way is a link (or not a real folder of this user's), or when the entry itself
  /// is a link, a hard link, a FIFO or a device: nothing may be written through it.
  std::filesystem::path file(const std::string& relative);
  /// Creates the sub-folder `relative` (recorded first), each folder on the way a real folder of
  /// this user's, none reached through a link. Throws WriteError.
  std::filesystem::path sub_folder(const std::string& relative);

  /// Deletes what earlier jobs recorded whose relative path starts with `prefix` (files, then
  /// the recorded folders that are then empty); a path that leads through a symbolic link or
  /// out of the folder is left alone. Returns how many files were deleted.
  std::size_t remove_earlier(const std::string& prefix);
  /// Regular files under the sub-folder `relative` with the extension `ext` that no flexframe
  /// job recorded (left in place; a caller warns about them).
  std::size_t unrecorded_files(const std::string& relative, const std::string& ext) const;

 private:
  void rewrite_manifest();
  std::filesystem::path dir_;
  int lock_fd_ = -1;
  int manifest_fd_ = -1;
  bool reserve_held_ = false;
  std::mutex mutex_;
  std::set<std::string> recorded_;  // earlier jobs' entries still present, and this job's
};

}  // namespace ff::app
