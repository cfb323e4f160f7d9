#include "app/study.h"

#include "app/child_process.h"
#include "app/output_folder.h"
#include "core/frame/file_name.h"
#include "core/frame/input_file.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifdef FF_HAVE_MPI
// the C API only: Open MPI's deprecated C++ bindings would need libmpi_cxx
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#if !defined(OPEN_MPI) && !defined(MPICH_VERSION)
#error "app/study.cpp needs the real MPI header, not the sequential MUMPS stand-in (check the include path)"
#endif
#endif

#include "app/io/frame_checksum.h"
#include "app/io/mesh_import.h"
#include "app/io/machine_memory.h"
#include "app/process_memory.h"
#include "app/run_session.h"
#include "app/timed_run.h"
#include "core/model/error_bars.h"
#include "core/scene/reference_csv.h"
#include "core/scene/scene.h"
#include "core/scene/schema.h"
#include "render/graphics_context.h"
#include "render/plot.h"

extern char** environ;

namespace fs = std::filesystem;

namespace ff::app {

namespace {

struct Row {
  StudyVariant variant;
  std::string status, reason;
  std::vector<double> walls;  ///< one per repetition
  double wall_s = NAN, setup_s = NAN, run_s = NAN;
  double peak_mb = NAN;       ///< peak resident growth during the first repetition
  double cpu_s = NAN;         ///< CPU time of the process per repetition (median)
  bool shared = false;        ///< ran while other variants ran (wall time includes the contention)
  double metric = NAN, error = NAN, error_percent = NAN;
  long long steps = 0, iterations = 0, updates = 0;
  bool pareto = false;
  bool is_reference = false;
};

// A key whose value is a discretization's size: finer is smaller (a step, a mesh size) or larger
// (an element or node count); other keys (a policy, a tolerance) have no order to observe
enum class Refines { no, smaller, larger };
Refines refinement_of(const std::string& key) {
  std::string last = key.substr(key.rfind('.') == std::string::npos ? 0 : key.rfind('.') + 1);
  if (last == "dt" || last == "mesh_size") return Refines::smaller;
  if (last == "n1" || last == "n2" || key == "efg.nodes" || key == "fem.elements") return Refines::larger;
  return Refines::no;
}

// The metric's convergence along one varied discretization key, the other keys at their finest
// value: the observed order from its three finest levels (core/model/error_bars.md (R6)), or the
// formal order 2 from two, and the estimated error of its finest level with its bar; or why not.
struct AxisConvergence {
  std::string axis;
  std::vector<std::string> levels;  ///< value labels, finest first
  std::vector<double> metric;       ///< the metric at them
  LevelEstimate estimate;
  std::string note;  ///< why no estimate ("" with one)
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::vector<AxisConvergence> axis_convergence(const StudySpec& spec, const std::vector<Row>& rows) {
  std::vector<AxisConvergence> out;
  for (std::size_t a = 0; a < spec.axes.size(); ++a) {
    const StudyAxis& axis = spec.axes[a];
    AxisConvergence c;
    c.axis = axis.name();
    // every key of the axis must refine the same way (n1 and n2 together; not dt with a count)
    Refines way = axis.keys.empty() ? Refines::no : refinement_of(axis.keys.front());
    for (const std::string& key : axis.keys)
      if (refinement_of(key) != way) way = Refines::no;
    std::vector<double> sizes;
    for (const std::string& v : axis.values) {
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      sizes.push_back(end && *end == '\0' && std::isfinite(x) && x > 0 ? x : NAN);
    }
    if (way == Refines::no || std::any_of(sizes.begin(), sizes.end(), [](double x) { return std::isnan(x); })) {
      continue;  // not a discretization: nothing to observe
    }
    // the finest level is the last value; the values must refine towards it
    bool refining = true;
    for (std::size_t i = 1; i < sizes.size(); ++i)
      refining = refining && (way == Refines::larger ? sizes[i] > sizes[i - 1] : sizes[i] < sizes[i - 1]);
    // the rows along this axis: every other axis at its last (finest) value, or not varied in the row
    std::vector<double> at(axis.values.size(), NAN);
    for (const Row& r : rows) {
      if (r.variant.axis_labels.size() != spec.axes.size() || r.variant.axis_labels[a].empty()) continue;
      bool others_finest = true;
      for (std::size_t b = 0; b < spec.axes.size(); ++b)
        if (b != a && !r.variant.axis_labels[b].empty())
          others_finest = others_finest && r.variant.axis_labels[b] == spec.axes[b].label(spec.axes[b].values.size() - 1);
      if (!others_finest) continue;
      for (std::size_t i = 0; i < axis.values.size(); ++i)
        if (r.variant.axis_labels[a] == axis.label(i)) at[i] = r.metric;
    }
    std::vector<double> values, ratios;
    for (std::size_t i = axis.values.size(); i-- > 0 && values.size() < 3;) {
      if (!std::isfinite(at[i])) break;  // a level that did not run or has no metric ends the ladder
      c.levels.push_back(axis.label(i));
      c.metric.push_back(at[i]);
      values.push_back(at[i]);
      if (values.size() > 1) ratios.push_back(std::max(sizes[i], sizes[i + 1]) / std::min(sizes[i], sizes[i + 1]));
    }
    if (!refining) c.note = "its values do not refine towards the last one";
    else if (values.size() < 2) c.note = "fewer than two of its finest levels have the metric";
    else {
      c.estimate = estimate_from_levels(axis.name(), values, ratios, 2.0);
      if (!c.estimate.error) c.note = c.estimate.flag;
    }
    out.push_back(std::move(c));
  }
  return out;
}

/// Linear interpolation of y at x in a reference table (x scaled); throws outside the table.
double interpolate_reference(const StudyReference& r) {
  scene::ReferenceTable t;
  std::vector<double> xs, ys;
  try {
    t = scene::read_reference_csv(r.file);
    xs = t.column(r.x_column);
    ys = t.column(r.y_column);
  } catch (const std::runtime_error& e) {
    throw InputError(std::string("study reference: ") + e.what());
  }
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const double x0 = xs[i] * r.x_scale, x1 = xs[i + 1] * r.x_scale;
    if ((r.at - x0) * (r.at - x1) <= 0.0 && x0 != x1) return ys[i] + (ys[i + 1] - ys[i]) * (r.at - x0) / (x1 - x0);
  }
  throw InputError(r.file + ": x = " + std::to_string(r.at) + " lies outside column '" + r.x_column +
                   "' (times " + std::to_string(r.x_scale) + ")");
}

std::string reference_text(const StudyReference& r, double value) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", value);
  switch (r.kind) {
    case StudyReference::Kind::finest: return std::string(b) + " from the finest variant (every axis at its last value)";
    case StudyReference::Kind::value: return std::string(b) + " (" + r.source + ")";
    case StudyReference::Kind::table:
      return std::string(b) + " (" + r.source + "; " + fs::path(r.file).filename().string() + ", " + r.y_column +
             " at " + r.x_column + " x " + fmt("%g", r.x_scale) + " = " + fmt("%g", r.at) + ")";
    case StudyReference::Kind::scene: {
      std::string o;
      for (const std::string& s : r.overrides) o += " --set " + s;
      return std::string(b) + " from a run of " + fs::path(r.scene).stem().string() + o;
    }
  }
  return b;
}

/// What one variant's repetitions record in its run folder (runs/NNN/summary.json): enough to
/// rebuild its study row without running it again (--resume).
struct VariantRun {
  std::string status, reason;
  Metrics metrics;
  long long steps = 0, iterations = 0, updates = 0;
  double setup_s = NAN, run_s = NAN, peak_mb = NAN;
  std::vector<double> walls, cpus;  ///< one per repetition
  bool shared = false;              ///< other variants ran at the same time
  std::string scene_hash;           ///< scene_fingerprint when the run started (--resume compares it)
  std::vector<std::pair<std::string, std::string>> metrics_unreached;  ///< metrics without a value: why
};

using Json = nlohmann::ordered_json;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

double number_at(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : NAN;
}

/// What a variant's result depends on besides its overrides: the bytes of its scene file and of
/// the mesh files it imports (any `part.file`, relative to the scene, also one set by an override),
/// as "fnv1a64:<hex>" (a check for edits, not a cryptographic hash). --resume runs a variant again
/// when this differs from the one recorded with its result: the scene was edited in between.
/// Empty when the scene cannot be read (the run then reports that itself).
std::string scene_fingerprint(const std::string& scene, const std::vector<std::string>& overrides) {
  std::uint64_t h = io::kFnvOffset;
  // a regular file only, read in pieces: a mesh file may be large, and nothing of it is kept
  const auto add_file = [&](const fs::path& file) {
    const int fd = open_input_file(file.string(), 0, "", nullptr);
    if (fd < 0) return false;
    const std::string name = file.filename().string();
    h = io::fnv1a(h, name.data(), name.size());
    char buffer[1 << 16];
    for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) != 0;) {
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) break;
      h = io::fnv1a(h, buffer, static_cast<std::size_t>(n));
    }
    ::close(fd);
    return true;
  };
  if (!add_file(scene)) return {};
  std::string text;
  read_input_file(scene, &text, kMaxTextInputBytes, kTextInputBound, nullptr);
  std::vector<std::string> meshes = scene::part_files_in_text(text, scene);
  for (const std::string& o : overrides) {  // part[0].file="other.obj"
    const std::size_t eq = o.find('=');
    const std::string key = eq == std::string::npos ? std::string() : o.substr(0, eq);
    if (key.rfind("part[", 0) != 0 || key.size() < 6 || key.compare(key.size() - 6, 6, "].file") != 0) continue;
    std::string v = o.substr(eq + 1);
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'')) v = v.substr(1, v.size() - 2);
    meshes.push_back(v);
  }
  for (const std::string& m : meshes) {
    const fs::path file = fs::path(m).is_absolute() ? fs::path(m) : fs::path(scene).parent_path() / m;
    add_file(file);
  }
  char b[32];
  std::snprintf(b, sizeof b, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return b;
}

/// Written to a temporary name first, so a killed study never leaves half a summary behind.
void write_variant_run(const fs::path& file, const std::string& label, const std::string& scene,
                       const std::vector<std::string>& overrides, const VariantRun& r) {
  Json j;
  j["label"] = label;
  j["scene"] = scene;
  j["overrides"] = overrides;
  j["status"] = r.status;
  j["reason"] = r.reason;
  Json m = Json::object();
  for (const auto& [name, value] : r.metrics) m[name] = finite_or_null(value);
  Json unreached = Json::object();  // as run's summary.json: null with the reason
  for (const auto& [name, why] : r.metrics_unreached) {
    m[name] = nullptr;
    unreached[name] = why;
  }
  j["metrics"] = m;
  j["metrics_unreached"] = unreached;
  j["steps"] = r.steps;
  j["newton_iterations"] = r.iterations;
  j["jacobian_updates"] = r.updates;
  j["setup_s"] = finite_or_null(r.setup_s);
  j["run_s"] = finite_or_null(r.run_s);
  j["peak_memory_mb"] = finite_or_null(r.peak_mb);
  Json w = Json::array(), c = Json::array();
  for (double v : r.walls) w.push_back(finite_or_null(v));
  for (double v : r.cpus) c.push_back(finite_or_null(v));
  j["wall_s"] = w;
  j["cpu_s"] = c;
  j["shared"] = r.shared;
  j["scene_hash"] = r.scene_hash;
  fs::create_directories(file.parent_path());
  write_text_file(file, j.dump(2) + "\n");  // through a temporary, never through a link
}

/// The run recorded in `file` when it is of this variant (same scene and overrides) and has a status.
/// With `edited`, also only when it ran on the scene as it is now (scene_fingerprint); otherwise
/// *edited says what changed (--resume then runs the variant again and says so).
std::optional<VariantRun> read_variant_run(const fs::path& file, const StudyVariant& v,
                                           std::string* edited = nullptr) {
  std::string text;
  if (!read_input_file(file.string(), &text, kMaxTextInputBytes, kTextInputBound, nullptr)) return std::nullopt;
  Json j;
  try {
    j = Json::parse(text);
    if (j.value("scene", std::string()) != v.scene ||
        j.value("overrides", std::vector<std::string>()) != v.overrides)
      return std::nullopt;
    VariantRun r;
    r.status = j.value("status", std::string());
    if (r.status.empty()) return std::nullopt;
    r.scene_hash = j.value("scene_hash", std::string());
    if (edited) {
      const std::string now = scene_fingerprint(v.scene, v.overrides);
      if (r.scene_hash != now) {
        *edited = r.scene_hash.empty() ? "its result records no scene hash"
                                       : "its scene or mesh file changed since it ran (" + r.scene_hash + ", now " +
                                             (now.empty() ? std::string("unreadable") : now) + ")";
        return std::nullopt;
      }
    }
    r.reason = j.value("reason", std::string());
    const Json unreached = j.value("metrics_unreached", Json::object());
    for (const auto& [name, value] : j.at("metrics").items()) {
      if (value.is_null() && unreached.contains(name)) {
        r.metrics_unreached.emplace_back(name, unreached.at(name).get<std::string>());
        continue;
      }
      r.metrics.emplace_back(name, value.is_number() ? value.get<double>() : NAN);
    }
    r.steps = j.value("steps", 0LL);
    r.iterations = j.value("newton_iterations", 0LL);
    r.updates = j.value("jacobian_updates", 0LL);
    r.setup_s = number_at(j, "setup_s");
    r.run_s = number_at(j, "run_s");
    r.peak_mb = number_at(j, "peak_memory_mb");
    for (const Json& w : j.at("wall_s")) r.walls.push_back(w.is_number() ? w.get<double>() : NAN);
    for (const Json& c : j.at("cpu_s")) r.cpus.push_back(c.is_number() ? c.get<double>() : NAN);
    r.shared = j.value("shared", false);
    return r;
  } catch (const std::exception&) {  // unreadable: run the variant again
    return std::nullopt;
  }
}

/// One timed repetition in this process; the first (empty `out.status`) also records status,
/// metrics, counts and memory. Returns false when stopped (nothing recorded then); a variant that
/// throws (other than bad scene input, which propagates) is recorded as failed.
bool run_repetition(const std::string& scene, const std::vector<std::string>& overrides, VariantRun& out,
                    const std::atomic<bool>& stop) {
  const bool first = out.status.empty();
  if (first) out.scene_hash = scene_fingerprint(scene, overrides);  // before the run: an edit during it counts
  const double rss0 = resident_mb();
  const bool reset = first && reset_peak_resident();
  const double cpu0 = cpu_seconds();
  TimedRun r;
  try {
    r = timed_run(scene, overrides, stop);
  } catch (const scene::SceneError&) {
    throw;
  } catch (const std::exception& e) {
    if (stop) return false;
    out.status = "failed";
    out.reason = e.what();
    return true;
  }
  if (stop) return false;  // an interrupted run is no result: --resume runs it again
  const double cpu = cpu_seconds() - cpu0;
  if (out.walls.empty()) {
    out.setup_s = r.setup_s;
    out.run_s = r.run_s;
  }
  out.walls.push_back(r.total_s());
  out.cpus.push_back(cpu);
  if (first) {
    out.status = to_string(r.outcome.status);
    out.reason = r.outcome.reason;
    out.metrics = r.metrics;
    out.metrics_unreached = r.metrics_unreached;
    out.steps = r.totals.steps;
    out.iterations = r.totals.newton_iterations;
    out.updates = r.totals.jacobian_updates;
    out.peak_mb = reset ? std::max(0.0, peak_resident_mb() - rss0) : NAN;
  }
  return true;
}

/// A variant handed to a child process.
struct Task {
  std::size_t entry;  ///< row index, or rows.size() for the reference run
  StudyVariant variant;
  fs::path folder;
  int reps = 1;
};

/// The environment of a child: this one with the element loops on one thread, since the cores
/// go to the variants running side by side, and without the MPI launcher's variables: a child is a
/// process of its own, and with MUMPS's MPI build it starts MPI alone (core/solve/solver_ranks.h),
/// which a rank's inherited OMPI_/PMIX_ variables would turn into a failed attempt to join the job.
std::vector<std::string> child_environment() {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    const std::string s = *e;
    if (s.rfind("OMP_NUM_THREADS=", 0) == 0 || s.rfind("OPENBLAS_NUM_THREADS=", 0) == 0) continue;
    if (s.rfind("OMPI_", 0) == 0 || s.rfind("PMIX_", 0) == 0 || s.rfind("PMI_", 0) == 0 || s.rfind("ORTE_", 0) == 0)
      continue;
    env.push_back(s);
  }
  env.push_back("OMP_NUM_THREADS=1");
  env.push_back("OPENBLAS_NUM_THREADS=1");
  return env;
}

/// Starts `flexframe study-variant` for the task (the same binary, via /proc/self/exe, so a
/// rebuilt executable cannot sneak in); its output goes to the run folder's log.txt. -1 on failure.
pid_t spawn_task(const Task& t, bool shared, const std::vector<std::string>& env) {
  fs::create_directories(t.folder);
  std::vector<std::string> args{"flexframe", "study-variant", t.variant.scene, "--reps", std::to_string(t.reps),
                                "--result", (t.folder / "summary.json").string()};
  if (shared) args.push_back("--shared");
  if (!t.variant.overrides.empty()) {
    args.push_back("--set");
    args.insert(args.end(), t.variant.overrides.begin(), t.variant.overrides.end());
  }
  // it ends (interrupted, its records written) when the study dies, even by SIGKILL
  ChildSpec spec;
  spec.program = "/proc/self/exe";
  spec.args = std::move(args);
  spec.env = env;
  spec.log = (t.folder / "log.txt").string();
  spec.stderr_to_log = true;
  return spawn_child(spec);
}

/// What a finished child left in its run folder; a crashed or killed one is reported with how it
/// ended, so the others go on.
VariantRun collect_child(const Task& t, int wait_status) {
  std::optional<VariantRun> r = read_variant_run(t.folder / "summary.json", t.variant);
  if (r) return *r;
  VariantRun f;
  f.scene_hash = scene_fingerprint(t.variant.scene, t.variant.overrides);
  f.status = "failed";
  f.reason = WIFSIGNALED(wait_status) ? "its process was killed by signal " + std::to_string(WTERMSIG(wait_status))
                                      : "its process exited with code " + std::to_string(WEXITSTATUS(wait_status)) +
                                            " without a result";
  f.reason += " (log: " + (t.folder / "log.txt").string() + ")";
  return f;
}

/// How the runs side by side share the machine's memory: each task's estimated peak
/// (scene::estimated_run_bytes; 0 unknown) and the limit they share (0: none known).
struct MemoryShare {
  std::vector<double> task_bytes;
  double limit = 0.0;
  int most_side_by_side = 0;  ///< out: the most runs that ran at once
  bool held_back = false;     ///< out: a run waited for memory although a slot was free
};

/// Runs the tasks as child processes, at most `jobs` at a time, in order of the list as slots
/// free up, and only as many at once as their estimated peaks fit in the memory limit together
/// (a run alone may use all of it: its own check refuses what cannot fit); `done` gets each
/// task's run as it finishes and returns false to start no more. Returns false when stopped
/// (running children are asked to stop and waited for).
bool run_children(const std::vector<Task>& tasks, int jobs, bool shared, const std::atomic<bool>& stop,
                  const std::function<bool(const Task&, VariantRun&)>& done, MemoryShare* share = nullptr) {
  MemoryShare none;
  MemoryShare& memory = share ? *share : none;
  const std::vector<std::string> env = child_environment();
  std::vector<std::pair<pid_t, std::size_t>> running;
  std::size_t next = 0;
  bool more = true;
  const auto bytes_of = [&](std::size_t i) { return i < memory.task_bytes.size() ? memory.task_bytes[i] : 0.0; };
  const auto fits = [&](std::size_t i) {
    if (running.empty() || !(memory.limit > 0)) return true;
    double in_use = bytes_of(i);
    for (const auto& [pid, k] : running) in_use += bytes_of(k);
    return in_use <= memory.limit;
  };
  while ((more && next < tasks.size()) || !running.empty()) {
    while (more && !stop && next < tasks.size() && static_cast<int>(running.size()) < jobs) {
      if (!fits(next)) {
        memory.held_back = true;
        break;
      }
      const Task& t = tasks[next];
      const pid_t pid = spawn_task(t, shared, env);
      if (pid > 0) {
        running.emplace_back(pid, next);
        memory.most_side_by_side = std::max(memory.most_side_by_side, static_cast<int>(running.size()));
      } else {
        VariantRun r;
        r.status = "failed";
        r.reason = std::string("cannot start a process for it: ") + std::strerror(errno);
        more = done(t, r);
      }
      ++next;
    }
    if (stop) {
      for (const auto& [pid, i] : running) kill(pid, SIGTERM);
      for (const auto& [pid, i] : running) waitpid(pid, nullptr, 0);
      return false;
    }
    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      int st = 0;
      if (waitpid(it->first, &st, WNOHANG) != it->first) {
        ++it;
        continue;
      }
      reaped = true;
      const Task& t = tasks[it->second];
      it = running.erase(it);
      VariantRun r = collect_child(t, st);
      if (!done(t, r)) more = false;
    }
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

bool complete_timing(const VariantRun& r, int repeat, bool exclusive) {
  if (r.status != "completed") return true;  // nothing more to time
  return static_cast<int>(r.walls.size()) >= repeat && !(exclusive && r.shared);
}

/// Ranks of the world when started by mpirun (Open MPI) or a PMI launcher such as srun; 1 otherwise.
/// Read from the environment before any MPI call, so a plain `flexframe study` never starts MPI.
int world_size_from_env() {
  for (const char* key : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(key)) return std::max(1, std::atoi(v));
  return 1;
}

#ifdef FF_HAVE_MPI
// Every call goes through the PMPI_ names: the sequential MUMPS library in the same executable
// defines a fake MPI_Init / MPI_Comm_rank / MPI_Finalize that the dynamic linker may pick first;
// only the real MPI library defines PMPI_*.
constexpr int kResultTag = 1, kTaskTag = 2;

/// MPI for the study's lifetime, when launched with more than one rank.
struct MpiSession {
  bool active = false;
  int rank = 0, size = 1;
  int waiting = 0;  ///< rank 0: worker ranks not yet told to stop
  MpiSession() {
    if (world_size_from_env() < 2) return;
    PMPI_Init(nullptr, nullptr);
    PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
    PMPI_Comm_size(MPI_COMM_WORLD, &size);
    active = size > 1;
    if (active && rank == 0) waiting = size - 1;
  }
  ~MpiSession() {
    if (world_size_from_env() < 2) return;
    // rank 0 leaving early (an exception): answer every worker's next request with "stop", or
    // they would wait for it forever
    while (waiting > 0) {
      MPI_Status status;
      PMPI_Probe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &status);
      int n = 0;
      PMPI_Get_count(&status, MPI_CHAR, &n);
      std::string text(static_cast<std::size_t>(n), '\0');
      PMPI_Recv(text.data(), n, MPI_CHAR, status.MPI_SOURCE, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      int reply[2] = {-1, 1};
      PMPI_Send(reply, 2, MPI_INT, status.MPI_SOURCE, kTaskTag, MPI_COMM_WORLD);
      --waiting;
    }
    PMPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

/// A rank other than 0: asks rank 0 for an entry, runs it as a child process (one thread, as with
/// --jobs), sends back its summary.json text with the next request; the text travels so the run
/// folders need not be on a file system rank 0 shares.
int mpi_worker(const std::vector<StudyVariant>& entries, const std::vector<fs::path>& folders,
               const std::atomic<bool>& stop) {
  std::string message;  // "ENTRY\nJSON"; empty: nothing to report yet
  for (;;) {
    PMPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kResultTag, MPI_COMM_WORLD);
    int task[2] = {-1, 1};
    PMPI_Recv(task, 2, MPI_INT, 0, kTaskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task[0] < 0 || static_cast<std::size_t>(task[0]) >= entries.size()) return stop ? 130 : 0;
    const std::size_t e = static_cast<std::size_t>(task[0]);
    const Task t{e, entries[e], folders[e], task[1]};
    std::optional<VariantRun> got;
    run_children({t}, 1, true, stop, [&](const Task&, VariantRun& r) {
      got = r;
      return true;
    });
    message = std::to_string(e) + "\n";
    if (got) {  // a crash is reported like a result (collect_child), a stop sends none
      write_variant_run(t.folder / "summary.json", t.variant.label, t.variant.scene, t.variant.overrides, *got);
      message += read_text_or_empty(t.folder / "summary.json");
    }
  }
}

/// Rank 0: hands the tasks out one at a time as ranks ask (the longest runs need not be known in
/// advance), runs one itself in a child process between messages, and gathers every result into
/// its run folder. Polls with short sleeps, since a blocking receive in Open MPI spins a core
/// that its own variant needs. `workers` counts down the ranks told to stop. Returns false when
/// stopped.
bool run_distributed(const std::vector<Task>& tasks, int& workers, const std::atomic<bool>& stop,
                     const std::function<bool(const Task&, VariantRun&)>& done) {
  const std::vector<std::string> env = child_environment();
  std::map<std::size_t, std::size_t> task_of_entry;
  for (std::size_t i = 0; i < tasks.size(); ++i) task_of_entry[tasks[i].entry] = i;
  std::size_t next = 0;
  bool more = true;
  pid_t local = -1;
  std::size_t local_task = 0;
  for (;;) {
    bool busy = false;
    if (local < 0 && more && !stop && next < tasks.size()) {
      local_task = next++;
      local = spawn_task(tasks[local_task], true, env);
      if (local < 0) {
        VariantRun r;
        r.status = "failed";
        r.reason = std::string("cannot start a process for it: ") + std::strerror(errno);
        more = done(tasks[local_task], r) && more;
      }
      busy = true;
    }
    if (local > 0) {
      int st = 0;
      if (stop) {
        kill(local, SIGTERM);
        waitpid(local, nullptr, 0);
        local = -1;
      } else if (waitpid(local, &st, WNOHANG) == local) {
        local = -1;
        VariantRun r = collect_child(tasks[local_task], st);
        more = done(tasks[local_task], r) && more;
        busy = true;
      }
    }
    int flag = 0;
    MPI_Status status;
    PMPI_Iprobe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &flag, &status);
    if (flag) {
      busy = true;
      int n = 0;
      PMPI_Get_count(&status, MPI_CHAR, &n);
      std::string text(static_cast<std::size_t>(n), '\0');
      PMPI_Recv(text.data(), n, MPI_CHAR, status.MPI_SOURCE, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      const std::size_t nl = text.find('\n');
      if (nl != std::string::npos && nl + 1 < text.size()) {
        const auto it = task_of_entry.find(std::stoul(text.substr(0, nl)));
        if (it != task_of_entry.end()) {
          const Task& t = tasks[it->second];
          fs::create_directories(t.folder);
          write_text_file(t.folder / "summary.json", text.substr(nl + 1));
          VariantRun r = collect_child(t, 0);
          more = done(t, r) && more;
        }
      }
      int reply[2] = {-1, 1};
      if (more && !stop && next < tasks.size()) {
        reply[0] = static_cast<int>(tasks[next].entry);
        reply[1] = tasks[next].reps;
        ++next;
      } else {
        --workers;
      }
      PMPI_Send(reply, 2, MPI_INT, status.MPI_SOURCE, kTaskTag, MPI_COMM_WORLD);
    }
    if (workers == 0 && local < 0 && (stop || !more || next >= tasks.size())) break;
    if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return !stop;
}
#endif

}  // namespace

StudySpec make_study_spec(const StudyOptions& o) {
  StudySpec s;
  std::string file;
  for (const auto& [name, path] : bundled_studies())
    if (name == o.target) file = path;
  if (file.empty() && is_study_file(o.target)) file = o.target;
  if (!file.empty()) {
    s = read_study_file(file);
  } else {
    s.scene = resolve_scene(o.target);
    s.name = fs::path(s.scene).stem().string();
    if (o.vary.empty()) throw InputError("study of a scene needs at least one --vary KEY=V1,V2,...");
  }
  for (const std::string& v : o.vary) s.axes.push_back(parse_vary(v));
  for (const std::string& v : o.overrides) s.base_overrides.push_back(v);
  if (!o.overrides.empty()) {
    for (StudyVariant& v : s.extra) v.overrides.insert(v.overrides.end(), o.overrides.begin(), o.overrides.end());
    if (s.reference.kind == StudyReference::Kind::scene)
      s.reference.overrides.insert(s.reference.overrides.end(), o.overrides.begin(), o.overrides.end());
  }
  if (!o.metric.empty()) s.metric = o.metric;
  if (s.metric.empty()) throw InputError("study needs --metric NAME (a summary.json metric of the scene)");
  if (!o.baseline.empty()) s.reference = parse_reference("scene:" + o.baseline);
  if (!o.reference.empty()) s.reference = parse_reference(o.reference);
  if (s.reference.kind == StudyReference::Kind::scene && s.reference.overrides.empty())
    s.reference.overrides = s.base_overrides;
  if (o.each) s.grid = false;
  if (o.repeat) s.repeat = *o.repeat;
  if (s.axes.empty() && s.extra.empty()) throw InputError("study '" + s.name + "' has nothing to vary");
  return s;
}

int check_study(const StudySpec& spec) {
  std::vector<StudyVariant> runs = spec.variants();
  if (const std::optional<StudyVariant> r = spec.reference_run())
    if (std::none_of(runs.begin(), runs.end(), [&](const StudyVariant& v) { return v.same_run(*r); }))
      runs.push_back(*r);
  for (const StudyVariant& v : runs) {
    try {
      std::printf("%-50s %s\n", v.label.c_str(), scene::check_scene(v.scene, v.overrides, io::scene_context()).c_str());
    } catch (const scene::SceneError& e) {
      std::vector<scene::Issue> issues = e.issues;
      for (scene::Issue& i : issues) i.message += " (study '" + spec.name + "', variant " + v.label + ")";
      throw scene::SceneError(issues);
    }
  }
  if (spec.reference.kind == StudyReference::Kind::table)
    std::printf("reference %.6g from %s\n", interpolate_reference(spec.reference), spec.reference.file.c_str());
  std::printf("study %s: %zu runs valid\n", spec.name.c_str(), runs.size());
  return 0;
}

int run_study_variant(const StudyVariantOptions& o, const std::atomic<bool>& stop) {
  VariantRun r;
  r.shared = o.shared;
  try {
    for (int k = 0; k < std::max(1, o.reps); ++k) {
      if (!run_repetition(o.scene, o.overrides, r, stop)) return 130;
      if (r.status != "completed") break;
    }
  } catch (const scene::SceneError& e) {  // the parent refuses the study with this message
    r.status = "invalid";
    r.reason = e.what();
  }
  write_variant_run(o.result, "", o.scene, o.overrides, r);
  return 0;
}

// The runs of a study's entries (its variants, then the reference run when it is none of them),
// with what each phase needs of them
struct StudyRuns {
  const StudySpec& spec;
  const std::vector<StudyVariant>& entries;
  const std::vector<fs::path>& folders;
  std::vector<std::optional<VariantRun>> runs;
  std::size_t variants = 0;  ///< entries before the reference run
  bool ref_entry = false;    ///< the last entry is the reference run

  bool is_ref(std::size_t e) const { return ref_entry && e == variants; }
  std::string label_of(std::size_t e) const { return is_ref(e) ? "reference " + entries[e].label : entries[e].label; }
  void save(std::size_t e) const {
    write_variant_run(folders[e] / "summary.json", entries[e].label, entries[e].scene, entries[e].overrides, *runs[e]);
  }
  // a completed run without the metric: the metric name is wrong, not the variant
  void check_metric(std::size_t e) const {
    const VariantRun& r = *runs[e];
    if (r.status == "invalid")
      throw InputError("variant " + entries[e].label + " (study '" + spec.name + "'): " + locate_in_study_file(spec, r.reason));
    if (r.status == "completed" && !std::isfinite(metric(r.metrics, spec.metric))) {
      for (const auto& [name, why] : r.metrics_unreached)  // the scene has it; this run gave it no value
        if (name == spec.metric)
          throw InputError("variant " + label_of(e) + " (study '" + spec.name + "'): metric '" + spec.metric +
                           "' has no value: " + why);
      std::string names;
      for (const auto& [name, value] : r.metrics) names += " " + name;
      throw InputError("scene " + fs::path(entries[e].scene).stem().string() + " has no metric '" + spec.metric +
                       "'; its metrics are:" + names);
    }
  }
};

// The study's second phase, in this process, one at a time: runs still without a result, and with
// --timing exclusive the timed repetitions of runs made side by side; repetitions interleaved
// over the variants so drift of the machine spreads over all of them
void run_in_sequence(StudyRuns& book, bool exclusive, int repeat, const std::atomic<bool>& stop) {
  std::vector<std::size_t> todo;
  for (std::size_t e = 0; e < book.entries.size(); ++e) {
    if (!book.runs[e]) {
      todo.push_back(e);
    } else if (exclusive && !book.is_ref(e) && !complete_timing(*book.runs[e], repeat, true)) {
      if (book.runs[e]->shared) {  // its side-by-side times are replaced by exclusive ones
        book.runs[e]->walls.clear();
        book.runs[e]->cpus.clear();
        book.runs[e]->shared = false;
      }
      todo.push_back(e);
    }
  }
  const std::size_t total = todo.size() * repeat;
  std::size_t done = 0;
  for (int k = 0; k < repeat && !stop; ++k) {
    for (std::size_t e : todo) {
      if (stop) break;
      ++done;
      if (book.runs[e] && (book.runs[e]->status != "completed" || static_cast<int>(book.runs[e]->walls.size()) > k)) continue;
      if (k > 0 && book.is_ref(e)) continue;
      std::fprintf(stderr, "[%zu/%zu] %s ...", done, total, book.label_of(e).c_str());
      std::fflush(stderr);
      VariantRun r = book.runs[e] ? *book.runs[e] : VariantRun{};
      try {
        if (!run_repetition(book.entries[e].scene, book.entries[e].overrides, r, stop)) break;
      } catch (const scene::SceneError&) {
        std::fprintf(stderr, "\n");
        throw;
      }
      book.runs[e] = r;
      if (r.status == "failed") {
        std::fprintf(stderr, " failed: %s\n", r.reason.c_str());
      } else {
        std::fprintf(stderr, " %s, %s = %.6g, %.3f s\n", r.status.c_str(), book.spec.metric.c_str(),
                     metric(r.metrics, book.spec.metric), r.walls.back());
      }
      if (k == 0) {
        if (r.status == "completed" && !std::isfinite(metric(r.metrics, book.spec.metric))) std::fprintf(stderr, "\n");
        book.check_metric(e);
      }
      if (r.status != "completed" || static_cast<int>(r.walls.size()) >= repeat || book.is_ref(e)) book.save(e);
    }
  }
  // a shared run re-timed only in part keeps the new times in its folder, marked not complete
  for (std::size_t e : todo)
    if (book.runs[e] && book.runs[e]->status == "completed" && static_cast<int>(book.runs[e]->walls.size()) < repeat &&
        !book.is_ref(e) && !book.runs[e]->walls.empty())
      book.save(e);
}

// What a variant's run measured, into its row of the tables
void take_run(Row& row, const VariantRun& r, const std::string& metric_name) {
  row.status = r.status;
  row.reason = r.reason;
  row.walls = r.walls;
  row.cpu_s = median(r.cpus);
  row.shared = r.shared;
  row.metric = metric(r.metrics, metric_name);
  row.steps = r.steps;
  row.iterations = r.iterations;
  row.updates = r.updates;
  row.peak_mb = r.peak_mb;
  row.setup_s = r.setup_s;
  row.run_s = r.run_s;
}

// Each row's error against the reference and its median wall time; marks the Pareto front (no
// cheaper variant is as accurate). Returns the rows on the front's candidates, cheapest first,
// and sets *first_wall to the first variant's time (relative times are to it).
std::vector<std::size_t> rank_by_cost(std::vector<Row>& rows, double ref, double* first_wall_out) {
  const double scale = std::isfinite(ref) && ref != 0.0 ? std::abs(ref) : NAN;
  double first_wall = NAN;
  for (Row& r : rows) {
    r.wall_s = median(r.walls);
    if (!std::isfinite(first_wall) && std::isfinite(r.wall_s)) first_wall = r.wall_s;
    r.error = std::abs(r.metric - ref);
    r.error_percent = 100.0 * r.error / scale;
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (std::isfinite(rows[i].wall_s) && std::isfinite(rows[i].error) && !rows[i].is_reference) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rows[a].wall_s < rows[b].wall_s; });
  double best = INFINITY;
  // a variant must beat the cheaper ones by more than round-off to count
  for (std::size_t i : order)
    if (rows[i].error < best * (1.0 - 1e-6)) {
      best = rows[i].error;
      rows[i].pareto = true;
    }

  *first_wall_out = first_wall;
  return order;
}

// study.csv: one row per variant; non-finite values (a variant that diverged has no metric) are
// left empty, never "nan". WriteError (a full disk): exit 1.
void write_study_csv(OutputFolder& folder, const StudySpec& spec, const std::vector<Row>& rows, double ref,
                     double first_wall) {
  std::ostringstream csv;
  csv << "variant";
  for (const StudyAxis& a : spec.axes) csv << ',' << a.name();
  csv << ",status,wall_s,relative_time,setup_s,run_s,steps,newton_iterations,jacobian_updates,peak_memory_mb,"
      << spec.metric << ",reference,error,error_percent,pareto,is_reference,cpu_s,shared\n";
  const auto num = [](double v) {
    if (!std::isfinite(v)) return std::string();
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  const auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + '"';
  };
  for (const Row& r : rows) {
    csv << quoted(r.variant.label);
    for (const std::string& l : r.variant.axis_labels) csv << ',' << quoted(l);
    csv << ',' << r.status << ',' << num(r.wall_s) << ',' << num(r.wall_s / first_wall) << ',' << num(r.setup_s)
        << ',' << num(r.run_s) << ',' << r.steps << ',' << r.iterations << ',' << r.updates << ',' << num(r.peak_mb)
        << ',' << num(r.metric) << ',' << num(ref) << ',' << num(r.error) << ',' << num(r.error_percent) << ','
        << (r.pareto ? 1 : 0) << ',' << (r.is_reference ? 1 : 0) << ',' << num(r.cpu_s) << ','
        << (r.shared ? 1 : 0) << '\n';
  }
  write_text_file(folder.file("study.csv"), csv.str());

}

// study.md: what was run and how it was timed, the table, and the convergence per varied key
std::string study_markdown(const StudySpec& spec, const std::vector<Row>& rows, double ref, double first_wall,
                           int repeat, bool any_shared, int side_by_side, bool distributed) {
  std::ostringstream md;
  md << "# Study " << spec.name << "\n\n";
  if (!spec.description.empty()) md << spec.description << "\n\n";
  md << "- base scene: " << fs::path(spec.scene).stem().string();
  for (const std::string& s : spec.base_overrides) md << " `--set " << s << "`";
  md << "\n- metric: `" << spec.metric << "`; reference " << reference_text(spec.reference, ref) << "\n";
  md << "- wall time: median of " << repeat << " run(s) per variant (set-up + solve, no output)";
  if (any_shared)
    md << "; variants marked shared ran " << side_by_side << (distributed ? " at a time (MPI ranks)" : " at a time")
       << ", one thread each, so their times include"
       << " the contention (`--timing exclusive` re-times them one at a time)";
  else
    md << ", repetitions interleaved over the variants";
  md << "; relative time is to the first variant, measured in the same study; CPU time is the process's\n";
  md << "- peak memory: growth of the resident set during the variant's first run"
     << (std::isfinite(rows.empty() ? NAN : rows.front().peak_mb) ? "" : " (not measurable here: shown as -)")
     << "\n- Pareto: no faster variant has a smaller error\n\n";
  md << "| variant | wall [s] | CPU [s] | shared | relative time | Newton it. | matrix updates | peak memory [MB] | "
     << spec.metric << " | error [%] | Pareto | status |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << "| " << r.variant.label << " | " << fmt("%.3g", r.wall_s) << " | " << fmt("%.3g", r.cpu_s) << " | "
       << (r.shared ? "yes" : "") << " | " << fmt("%.3f", r.wall_s / first_wall)
       << " | " << r.iterations << " | " << r.updates << " | " << fmt("%.2f", r.peak_mb) << " | "
       << fmt("%.6g", r.metric) << " | " << (r.is_reference ? std::string("reference") : fmt("%.3g", r.error_percent))
       << " | " << (r.pareto ? "yes" : "") << " | " << r.status << (r.reason.empty() ? "" : ": " + r.reason)
       << " |\n";
  }
  // how the metric converges along each discretization key (error_bars.md (R6)): the observed
  // order, and the finest variant's own error, which the finest-variant reference leaves out
  const std::vector<AxisConvergence> convergence = axis_convergence(spec, rows);
  if (!convergence.empty()) {
    md << "\n## Convergence per varied key (core/model/error_bars.md)\n\n"
       << "Along each key, the other keys at their finest value: the observed order from the three finest "
          "levels (R6) (the formal order 2 from two), and the estimated error of the finest level with its "
          "bar (GCI, safety factor 1.25 observed / 3 formal).\n\n"
       << "| key | levels, finest first | " << spec.metric << " | order | estimated error of the finest | bar |\n"
       << "|---|---|---|---|---|---|\n";
    double total = 0.0, total_bar = 0.0;
    bool all = true;
    for (const AxisConvergence& c : convergence) {
      std::string levels, values;
      for (std::size_t i = 0; i < c.levels.size(); ++i) {
        levels += (i ? ", " : "") + c.levels[i];
        values += (i ? ", " : "") + fmt("%.6g", c.metric[i]);
      }
      md << "| " << c.axis << " | " << levels << " | " << values << " | ";
      if (c.estimate.error) {
        const SourceError& e = *c.estimate.error;
        md << fmt("%.2f", e.order) << (e.order_observed            ? " (observed)"
                                         : e.observed_order > 0.0 ? fmt(" (formal; observed %.2f)", e.observed_order)
                                                                  : std::string(" (formal)")) << " | " << fmt("%.3g", e.estimate)
           << " (" << fmt("%.2g", 100.0 * std::abs(e.estimate) / std::max(std::abs(e.fine), 1e-300)) << " %) | "
           << fmt("%.3g", e.bar) << " |\n";
        total += e.estimate;
        total_bar += e.bar;
      } else {
        md << "- | no estimate: " << c.note << " | |\n";
        all = false;
      }
    }
    if (spec.reference.kind == StudyReference::Kind::finest && total_bar > 0)
      md << "\nThe errors above are measured from the finest variant, whose own error is estimated at "
         << fmt("%.3g", total) << " ± " << fmt("%.3g", total_bar) << " (the keys' estimates and bars added, (R7))"
         << (all ? "" : "; keys without an estimate are not in it") << ".\n";
  }
  return md.str();

}

// pareto.png: error against wall time, log-log; a line per value of the later axes. Returns the
// line that says what it shows ("" when it could not be drawn: a warning said why).
std::string draw_pareto_plot(OutputFolder& folder, const StudySpec& spec, const std::vector<Row>& rows,
                             const std::vector<std::size_t>& order) {
  std::string err, pareto_note;
  auto gc = render::GraphicsContext::create(&err);
  if (gc) {
    render::PlotSpec plot;
    plot.title = spec.name + ": error of " + spec.metric + " against wall time";
    plot.x_label = "wall time [s]";
    plot.y_label = "error in " + spec.metric + " [%]";
    plot.log_x = plot.log_y = true;
    // the front first, in grey, so that the variants' markers are drawn over it
    render::PlotSeries front{"Pareto front", {}, {}, false};
    front.grey = true;
    front.dash = render::LineDash::dashed;
    for (std::size_t i : order)
      if (rows[i].pareto) {
        front.x.push_back(rows[i].wall_s);
        front.y.push_back(rows[i].error_percent);
      }
    const bool draw_front = front.x.size() > 1;
    if (draw_front) plot.series.push_back(front);
    // the second varied key's value picks a marker shape (colours tell the series apart as well)
    constexpr render::MarkerShape kShapes[] = {render::MarkerShape::circle, render::MarkerShape::square,
                                               render::MarkerShape::diamond, render::MarkerShape::cross,
                                               render::MarkerShape::plus};
    std::map<std::string, std::size_t> shape_of;
    std::map<std::string, std::size_t> series_of;
    for (const Row& r : rows) {
      std::string group;
      bool axis_row = false;
      for (std::size_t a = 0; a < r.variant.axis_labels.size(); ++a) {
        if (!r.variant.axis_labels[a].empty()) axis_row = true;
        if (a == 0 && spec.grid) continue;  // points along the first axis share a line
        if (!r.variant.axis_labels[a].empty())
          group += (group.empty() ? "" : ", ") + spec.axes[a].name() + "=" + r.variant.axis_labels[a];
      }
      if (!axis_row) group = r.variant.label;
      if (group.empty()) group = spec.axes.empty() ? "variants" : spec.axes.front().name();
      auto [it, fresh] = series_of.emplace(group, plot.series.size());
      if (fresh) {
        render::PlotSeries s{group, {}, {}, true};  // markers: neighbours are not a continuum in time
        if (r.variant.axis_labels.size() > 1 && !r.variant.axis_labels[1].empty()) {
          const auto [shape, unused] = shape_of.emplace(r.variant.axis_labels[1], shape_of.size());
          s.marker = kShapes[shape->second % std::size(kShapes)];
        }
        plot.series.push_back(s);
      }
      render::PlotSeries& s = plot.series[it->second];
      s.x.push_back(r.wall_s);
      s.y.push_back(r.error_percent);
      // a point on the front says which value of the (first) varied key it is
      std::string tag;
      if (r.pareto) {
        for (std::size_t a = 0; a < r.variant.axis_labels.size() && a < spec.axes.size(); ++a)
          if (tag.empty() && !r.variant.axis_labels[a].empty())
            tag = spec.axes[a].name() + "=" + r.variant.axis_labels[a];
        if (tag.empty()) tag = r.variant.label;  // an extra variant (another scene) varies no key
      }
      s.point_labels.push_back(tag);
    }
    // a plot with nothing to draw (every variant stopped early) is a warning; a file that
    // cannot be written is the study's failure
    render::PlotDrawn drawn;
    if (!render::write_plot_png(*gc, plot, folder.file("pareto.png").string(), &err, &drawn)) {
      if (err.find("could not write PNG") != std::string::npos) throw WriteError("pareto plot: " + err);
      std::fprintf(stderr, "warning: pareto plot: %s\n", err.c_str());
    } else {
      pareto_note = fmt("pareto.png: error axis %.3g", drawn.y_min) + fmt(" to %.3g %%", drawn.y_max) + ", " +
                    std::to_string(drawn.point_labels) + " Pareto point(s) labelled\n";
    }
  } else {
    std::fprintf(stderr, "warning: no graphics context for pareto.png: %s\n", err.c_str());
  }
  return pareto_note;
}

int run_study(const StudySpec& spec, const StudyOptions& options, const std::atomic<bool>& stop) {
  const fs::path dir = options.out_dir.empty() ? fs::path("out") / "study" / spec.name : fs::path(options.out_dir);
  const fs::path runs_dir = dir / "runs";
#ifdef FF_HAVE_MPI
  MpiSession mpi;
  const bool worker = mpi.active && mpi.rank != 0;
#else
  if (world_size_from_env() > 1)
    throw InputError("this flexframe was built without MPI: run the study without mpirun (--jobs N uses this "
                     "machine's cores)");
  const bool worker = false;
#endif
  // only rank 0 owns the output folder; its lock comes before any file in it is touched
  std::optional<OutputFolder> folder;
  if (!worker) {
    if (options.out_dir.empty())  // a study file's name was checked there; this is the last word
      if (const std::string why = file_name_problem(spec.name); !why.empty())
        throw InputError("the study name '" + spec.name + "' " + why + "; give --out");
    folder.emplace(dir, "study");
    // stale runs of another study must not be resumed: what earlier studies recorded goes
    if (!options.resume) folder->remove_earlier("runs/");
    folder->sub_folder("runs");
  }
  const int jobs = options.jobs > 0 ? options.jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const bool exclusive = options.exclusive_timing;
  const int repeat = std::max(1, spec.repeat);

  std::vector<Row> rows;
  for (const StudyVariant& v : spec.variants()) {
    rows.emplace_back();
    rows.back().variant = v;
    rows.back().status = "not run";
  }
  // entries: the rows, then the reference run when it is none of them
  std::vector<StudyVariant> entries;
  std::vector<fs::path> folders;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    char b[32];
    std::snprintf(b, sizeof b, "%03zu", i);
    entries.push_back(rows[i].variant);
    folders.push_back(runs_dir / b);
  }

  // the reference: a number, a run outside the variants, or the finest variant
  double ref = NAN;
  std::size_t ref_row = rows.size();
  bool ref_entry = false;
  switch (spec.reference.kind) {
    case StudyReference::Kind::value: ref = spec.reference.value; break;
    case StudyReference::Kind::table: ref = interpolate_reference(spec.reference); break;
    case StudyReference::Kind::scene:
    case StudyReference::Kind::finest: {
      const StudyVariant target = *spec.reference_run();
      for (std::size_t i = 0; i < rows.size(); ++i)
        if (rows[i].variant.same_run(target)) ref_row = i;
      if (ref_row == rows.size()) {
        ref_entry = true;
        entries.push_back(target);
        folders.push_back(runs_dir / "reference");
      }
    }
  }

  // every run folder and what goes into it is in the manifest before any child writes it
  if (folder)
    for (const fs::path& f : folders) {
      const std::string rel = "runs/" + f.filename().string();
      folder->sub_folder(rel);
      for (const char* file : {"summary.json", "log.txt"}) folder->file(rel + "/" + file);  // refuses a planted link
    }
#ifdef FF_HAVE_MPI
  if (worker) return mpi_worker(entries, folders, stop);
#endif
  StudyRuns book{spec, entries, folders, std::vector<std::optional<VariantRun>>(entries.size()), rows.size(), ref_entry};
  std::vector<std::optional<VariantRun>>& runs = book.runs;
  if (options.resume) {
    std::size_t n = 0;
    for (std::size_t e = 0; e < entries.size(); ++e) {
      std::string edited;
      runs[e] = read_variant_run(folders[e] / "summary.json", entries[e], &edited);
      if (!edited.empty())
        std::fprintf(stderr, "resume: %s runs again: %s\n", book.label_of(e).c_str(), edited.c_str());
      // bad input is checked again (and refused again) rather than taken over
      if (runs[e] && runs[e]->status == "invalid") runs[e].reset();
      if (runs[e] && !book.is_ref(e) && !exclusive && !complete_timing(*runs[e], repeat, false)) runs[e].reset();
      if (runs[e]) ++n;
    }
    std::fprintf(stderr, "resume: %zu of %zu runs recovered from %s\n", n, entries.size(), runs_dir.string().c_str());
  }

  // 1. side by side: every run without a result, each in its own single-threaded process
  std::vector<Task> tasks;
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (!runs[e]) tasks.push_back({e, entries[e], folders[e], exclusive || book.is_ref(e) ? 1 : repeat});
  // from the end of the table: axes go coarse to fine, so the costly runs start first and the
  // cheap ones fill the gaps, instead of the finest starting last and finishing alone
  std::reverse(tasks.begin(), tasks.end());
  bool stopped = false;
#ifdef FF_HAVE_MPI
  const bool distributed = mpi.active;
#else
  const bool distributed = false;
#endif
  // under MPI always: the other ranks wait for rank 0's word even when nothing is left to run
  int side_by_side = 1;
  if (distributed || (jobs > 1 && tasks.size() > 1)) {
    const int slots = std::min<int>(jobs, static_cast<int>(tasks.size()));
    side_by_side = distributed ? world_size_from_env() : slots;
    if (!tasks.empty() && distributed)
      std::fprintf(stderr, "%zu runs over %d MPI ranks, one at a time per rank (one thread each)%s\n", tasks.size(),
                   side_by_side, exclusive ? "; then the timed repetitions one at a time" : "");
    else if (!tasks.empty())
      std::fprintf(stderr, "%zu runs, %d at a time (one thread each)%s\n", tasks.size(), slots,
                   exclusive ? "; then the timed repetitions one at a time" : "");
    std::size_t done = 0;
    const auto report = [&](const Task& t, VariantRun& r) {
      runs[t.entry] = std::move(r);
      const VariantRun& v = *runs[t.entry];
      std::fprintf(stderr, "[%zu/%zu] %s: %s, %s = %.6g, %.3f s wall, %.3f s CPU%s%s\n", ++done, tasks.size(),
                   book.label_of(t.entry).c_str(), v.status.c_str(), spec.metric.c_str(), metric(v.metrics, spec.metric),
                   v.walls.empty() ? NAN : v.walls.front(), v.cpus.empty() ? NAN : v.cpus.front(),
                   v.reason.empty() ? "" : ": ", v.reason.c_str());
      // bad input in one variant ends the study as in sequence: start no more
      return v.status != "invalid" && (v.status != "completed" || std::isfinite(metric(v.metrics, spec.metric)));
    };
#ifdef FF_HAVE_MPI
    if (distributed)
      stopped = !run_distributed(tasks, mpi.waiting, stop, report);
    else
#endif
    {
      // the runs side by side share the memory limit: each is checked against all of it alone, so
      // four 0.45 GB runs would start together under a 1 GB limit
      MemoryShare memory;
      memory.limit = io::machine_memory_limit_bytes();
      for (const Task& t : tasks)
        memory.task_bytes.push_back(scene::estimated_run_bytes(t.variant.scene, t.variant.overrides, io::scene_context()));
      stopped = !run_children(tasks, slots, true, stop, report, &memory);
      if (memory.held_back)
        std::fprintf(stderr, "memory: at most %d run%s side by side (their estimated peaks together within the %.3g GB "
                             "limit; FLEXFRAME_MEMORY_LIMIT_GB sets it)\n",
                     memory.most_side_by_side, memory.most_side_by_side == 1 ? "" : "s", memory.limit / 1e9);
    }
    for (const Task& t : tasks)
      if (runs[t.entry]) book.check_metric(t.entry);
  }

  // 2. in this process, one at a time: what is still to run or to time
  if (!stopped) run_in_sequence(book, exclusive, repeat, stop);

  for (std::size_t i = 0; i < rows.size(); ++i)
    if (runs[i]) take_run(rows[i], *runs[i], spec.metric);
  const bool any_shared = std::any_of(rows.begin(), rows.end(), [](const Row& r) { return r.shared; });
  if (ref_entry) {
    if (runs.back()) ref = metric(runs.back()->metrics, spec.metric);
    if (!std::isfinite(ref) && !stop)
      throw InputError("the reference run (" + entries.back().label + ") has no finite metric '" + spec.metric +
                       "' (status " + (runs.back() ? runs.back()->status : std::string("not run")) + ")");
  }
  if (ref_row < rows.size()) {
    ref = rows[ref_row].metric;
    rows[ref_row].is_reference = true;
  }

  double first_wall = NAN;
  const std::vector<std::size_t> order = rank_by_cost(rows, ref, &first_wall);
  write_study_csv(*folder, spec, rows, ref, first_wall);
  const std::string md = study_markdown(spec, rows, ref, first_wall, repeat, any_shared, side_by_side, distributed);
  write_text_file(folder->file("study.md"), md);
  const std::string pareto_note = draw_pareto_plot(*folder, spec, rows, order);
  std::cout << md;
  std::printf("\n%s", pareto_note.c_str());
  std::printf("wrote %s/{study.csv, study.md, pareto.png}\n", dir.string().c_str());
  return stop ? 130 : 0;
}

}  // namespace ff::app
