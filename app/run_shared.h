#pragma once
/// \file run_shared.h
/// What the threads of one headless run share (run_session.cpp wires them): results.h5 with
/// the lock its users take turns under, and the run's first failed write, which stops the
/// solver and becomes the outcome.

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>

#include "app/io/results.h"
#include "app/output_folder.h"
#include "core/frame/frame.h"

namespace ff::app {

/// results.h5 while a run writes it. One user at a time under `mutex`: the store thread's
/// appends, the closing at the end and, over MPI ranks, the launcher watchdog, which may close
/// it while the solver thread is blocked (launcher_watchdog.h).
struct StoredResults {
  std::unique_ptr<io::ResultWriter> writer;
  std::mutex mutex;
  std::atomic<bool> closed{false};  ///< set under `mutex`; nothing touches the writer after
  /// the last frame appended (set with the append, so a stop names the last frame in the file)
  std::atomic<double> last_time{0.0};
  std::atomic<long long> last_step{0};
};

/// The first output of a run that could not be written. Recording one frees the folder's
/// reserve (room for the outcome in results.h5 and for summary.json) and stops the solver
/// through `run_stop`: the run then ends `failed` (exit 1) with it as the reason.
class WriteFailure {
 public:
  WriteFailure(OutputFolder& folder, std::atomic<bool>& run_stop) : folder_(folder), run_stop_(run_stop) {}
  void fail(const std::string& what) {
    {
      std::lock_guard lock(mutex_);
      if (first_.empty()) first_ = what;
    }
    folder_.release_reserve();
    run_stop_ = true;
  }
  /// "" while every write succeeded
  std::string what() const {
    std::lock_guard lock(mutex_);
    return first_;
  }
  bool any() const { return !what().empty(); }

 private:
  OutputFolder& folder_;
  std::atomic<bool>& run_stop_;
  mutable std::mutex mutex_;
  std::string first_;
};

/// The solver's outcome once its thread returned: the progress loop wakes at once, and the
/// launcher watchdog reads it to tell a stop during the solve from one while outputs were made.
struct SolverEnd {
  std::mutex mutex;
  std::condition_variable signal;
  std::atomic<bool> done{false};
  RunOutcome outcome;  ///< under `mutex`, once done
  void finish(const RunOutcome& o) {
    {
      std::lock_guard lock(mutex);
      outcome = o;
      done = true;
    }
    signal.notify_all();
  }
};

}  // namespace ff::app
