#pragma once
/// \file sim_worker.h
/// The GUI's solver thread. It owns the scene's Simulation; the UI talks to it only through a
/// command queue (run, pause, step, reset, set, edit, load_text, probe, pace, quit) and reads back plain
/// copies (the latest Frame, probe samples, a status) with take(). No GL or ImGui here.
///
/// How it works: the worker drives the scene's Simulation with a RunLoop (core/model/run_loop.h),
/// one advance() at a time, and applies the queued commands between steps; pausing is simply not
/// stepping (it waits for a command), so the solver's state never leaves its thread.
/// The scene is a TOML text (scene_draft.h): the worker holds the text in effect, and every
/// command that changes the model (reset, set, edit, load_text) builds a new Simulation from a new
/// text first (a refused one leaves the running model and its text alone and says why), then stops
/// the current run and starts the new one at t = 0, paused unless it was running. A `set` of a key
/// the scene schema declares live (scene::change_live: torque.amplitude, gravity.g) made after t = 0
/// changes the running model instead, and is written into the text as a [[timeline]] entry at the
/// time it took effect, so the text always reproduces the run.
/// A pause between output frames publishes the state reached. A probe is answered at once with a
/// Sample of the last published state for the new node (Sample::probe_answer), so the window has
/// the node's values whether paused, stepping, running or finished; each Sample names its node.

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/gui/scene_draft.h"
#include "core/frame/frame.h"
#include "core/scene/scene.h"
#include "core/scene/scene_selections.h"

namespace ff {
class RunLoop;
}

namespace ff::app::gui {

/// One point of the live plots: the state of a published frame, and the probed node in it.
/// A probe command is answered at once with a sample of the last published state for the new
/// node (same step as the frame before it), so a window never shows a node without its values.
struct Sample {
  std::int64_t step = 0;
  double time = 0.0;
  double load_factor = 0.0;
  std::vector<double> probes;   ///< in the order of RunInfo::probes
  int node = -1;                ///< the node the node_* values describe; -1: none probed
  std::array<double, 3> node_position{0, 0, 0};  ///< probed node, world coordinates
  double node_displacement = 0.0;  ///< |x - X| of the probed node
  double node_deflection = 0.0;    ///< |x - x_base|: its elastic part (0 without base points)
  bool has_deflection = false;     ///< the frame carried base points (a rigid motion to take off)
  bool probe_answer = false;       ///< answers a probe command: the state of the sample before it
  StepStats stats;
};

enum class WorkerState { paused, running, stepping, finished, failed };
const char* to_string(WorkerState s);

/// What the worker reports; a copy is handed out by take().
struct WorkerStatus {
  std::uint64_t generation = 0;  ///< +1 at every (re)build; samples belong to this generation
  std::uint64_t settled_seq = 0; ///< every command up to this sequence number has taken effect
  WorkerState state = WorkerState::paused;
  std::string scene_path;   ///< names the text in messages; relative mesh files are read from its folder
  std::string scene_text;   ///< the scene in effect: it reproduces this run (live edits as [[timeline]])
  std::string opened_text;  ///< the text as opened (a file or a new problem): what "edited" compares with
  std::string opened_from;  ///< the file it was opened from; "" for a new problem
  std::string scene_name;
  /// the nodes each [[bc]], [[load]], [[probe]], [[joint]], [[arc]] entry acts on (shell scenes;
  /// empty when they could not be worked out), for highlighting them on the body
  std::shared_ptr<const std::vector<scene::EntrySelection>> selections;
  /// the structure's named patch edges (patch name, edge name), for picking an edge from a list
  std::shared_ptr<const std::vector<std::pair<std::string, std::string>>> patch_edges;
  std::shared_ptr<const RunInfo> info;  ///< of this generation
  scene::OutputSettings output;
  double end_time = 0.0;
  long long steps_per_frame = 1;        ///< solver steps between published frames (the output cadence)
  int probe_node = -1;
  double pace = 0.0;                    ///< max steps per second, 0 = as fast as it goes
  std::optional<RunOutcome> outcome;    ///< once the run has ended
  Metrics metrics;                      ///< the scene's metrics, once the run has ended
  /// the modes of an eigen-analysis (scene.analysis = modal / buckling), once its run has ended;
  /// about the last published frame
  std::shared_ptr<const ModeSet> modes;
  std::string message;                  ///< the last refusal or notice ("" = none)
  std::uint64_t message_seq = 0;        ///< +1 per message
  bool message_is_error = false;
  std::uint64_t revision = 0;           ///< +1 at every change of the status, a frame or a sample
};

/// What take() returns: the status plus what arrived since the last take().
struct WorkerUpdate {
  WorkerStatus status;
  std::optional<Frame> frame;   ///< the newest frame, if a new one came
  std::vector<Sample> samples;  ///< every frame's sample since the last take, in order
};

class SimWorker {
 public:
  /// Starts the thread on a scene already loaded (so bad input is reported before any window
  /// opens); paused at the initial state. `on_change` is called (on the worker thread, under its
  /// lock: it must only post a wake-up, e.g. glfwPostEmptyEvent) whenever take() has news, so the
  /// window can sleep until then instead of polling.
  /// `scene_text` is the text `scene` was built from; `opened_text` and `opened_from` as in WorkerStatus.
  SimWorker(scene::LoadedScene scene, std::string scene_text, std::string opened_text, std::string opened_from,
            std::function<void()> on_change = {});
  ~SimWorker();  ///< quits and joins
  SimWorker(const SimWorker&) = delete;
  SimWorker& operator=(const SimWorker&) = delete;

  // Each returns the command's sequence number (compare with WorkerStatus::settled_seq).
  std::uint64_t run();
  std::uint64_t pause();
  /// Advances n solver steps (not output frames), then pauses and shows the state reached.
  std::uint64_t step(long long n = 1);
  std::uint64_t reset();
  std::uint64_t set(const std::string& key, const std::string& value);
  /// A set-up edit (scene_draft.h) of the text in effect when it is handled (after the edits
  /// queued before it); `what` names it in messages ("add bc").
  using DraftOp = std::function<DraftEdit(const std::string& text, const std::string& path)>;
  std::uint64_t edit(const std::string& what, DraftOp op);
  /// Opens a scene text (a file's, or a new problem's); `path` names it (and is where relative
  /// files are read from); `opened_from` as in WorkerStatus.
  std::uint64_t load_text(const std::string& text, const std::string& path, const std::string& opened_from);
  std::uint64_t probe(int node);
  std::uint64_t pace(double steps_per_second);

  WorkerUpdate take();

 private:
  struct Command {
    enum class Kind { run, pause, step, reset, set, edit, load_text, probe, pace, quit };
    Kind kind = Kind::run;
    std::string a, b, c;
    DraftOp op;
    long long n = 0;
    double x = 0.0;
    std::uint64_t seq = 0;
    static Command make(Kind k, std::string a = {}, std::string b = {}, long long n = 0, double x = 0.0) {
      Command c;
      c.kind = k, c.a = std::move(a), c.b = std::move(b), c.n = n, c.x = x;
      return c;
    }
  };
  std::uint64_t push(Command c);
  void main();
  /// The run loop's publish callback (worker thread): hands a frame over to the mailbox.
  void on_frame(Frame&& f);
  /// The sample of a published state for a node (-1: none).
  Sample sample_of(const Frame& f, int node) const;
  void handle(const Command& c, std::unique_lock<std::mutex>& lock);
  /// Applies queued commands; waits while paused. Returns when the run should go on or stop.
  void serve(std::unique_lock<std::mutex>& lock);
  void start_generation();
  void set_message(std::string text, bool error);
  bool settled() const;
  /// Marks the mailbox changed (under mutex_) and wakes the window.
  void changed();

  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Command> queue_;
  std::uint64_t next_seq_ = 1;
  std::uint64_t handled_seq_ = 0;

  // worker-owned solver state (touched only on the worker thread)
  scene::LoadedScene scene_;
  std::optional<scene::LoadedScene> pending_;
  std::string pending_text_, pending_opened_text_, pending_opened_from_;
  std::shared_ptr<const std::vector<scene::EntrySelection>> pending_selections_;
  std::shared_ptr<const std::vector<std::pair<std::string, std::string>>> pending_patch_edges_;
  /// Works out what a scene text's entries select (selections, patch_edges) for the window.
  static void find_selections(const std::string& text, const std::string& path,
                              std::shared_ptr<const std::vector<scene::EntrySelection>>* selections,
                              std::shared_ptr<const std::vector<std::pair<std::string, std::string>>>* patch_edges);
  std::atomic<bool> stop_{false};
  std::string failure_;  // an exception out of the solver ends the run as failed
  bool running_ = false;
  long long steps_left_ = 0;  // solver steps a Step still asks for
  bool quit_ = false;
  bool finished_ = false;
  int probe_node_ = -1;
  // the last published state of this generation (no fields, no step log): a probe is answered
  // from it at once, whether paused, stepping, finished or running
  std::optional<Frame> last_published_;
  // a pause between output frames publishes the state reached (so the view, the status line and
  // a probe agree with the solver); set by a pause, done by serve() before it waits
  bool show_reached_state_ = false;
  RunLoop* loop_ = nullptr;  // the run of this generation, while main() drives it
  double pace_ = 0.0;
  std::chrono::steady_clock::time_point last_release_;

  // the mailbox (under mutex_)
  WorkerStatus status_;
  std::optional<Frame> frame_;
  std::vector<Sample> samples_;

  std::function<void()> on_change_;
  std::thread thread_;
};

}  // namespace ff::app::gui
