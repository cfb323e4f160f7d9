/// \file result_writer.cpp
/// ResultWriter: RunInfo once, then frames staged in memory and written in blocks, each
/// block ending with a two-step H5Fflush (see results.h for why, results_layout.md for what).

#include <fcntl.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <set>

#include "app/io/frame_checksum.h"
#include "app/io/h5_util.h"
#include "app/io/results.h"
#include "app/io/results_names.h"
#include "core/frame/file_name.h"
#include "core/frame/output_file.h"

namespace ff::io {

namespace {

using Clock = std::chrono::steady_clock;

static_assert(std::endian::native == std::endian::little, "checksums hash little-endian rows");

// frame-indexed data sets are chunked along the frame axis: ~256 KiB chunks for per-point
// data, 1024 frames (8 KiB) for scalar series
constexpr std::size_t kChunkBytes = 256 * 1024;
constexpr hsize_t kMaxChunkFrames = 256;
constexpr hsize_t kScalarChunkFrames = 1024;
// room kept for the metadata a flush rewrites (object headers, B-tree nodes, attributes)
constexpr std::uint64_t kMetadataMarginBytes = 64 * 1024;

/// One extendible data set of shape (frames, frame_shape...) and its staged rows.
struct Column {
  std::string name;                  // path, for messages
  h5::Handle dset;
  std::vector<hsize_t> frame_shape;  // shape of one frame's row
  hid_t mem_type = H5I_INVALID_HID;  // not owned
  std::size_t row_bytes = 0;
  std::vector<unsigned char> staged;
  std::size_t chunk_rows = 1;  // frames per chunk (chunks are allocated and written whole)

  void stage(const void* row) {
    auto* b = static_cast<const unsigned char*>(row);
    staged.insert(staged.end(), b, b + row_bytes);
  }
};

Column make_column(hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                   std::size_t element_bytes, const std::vector<hsize_t>& frame_shape,
                   const std::string& description, const std::string& unit, const void* fill) {
  Column c;
  c.name = name;
  c.frame_shape = frame_shape;
  c.mem_type = mem_type;
  std::size_t elements = 1;
  for (hsize_t d : frame_shape) elements *= static_cast<std::size_t>(d);
  c.row_bytes = elements * element_bytes;

  std::vector<hsize_t> dims{0}, max_dims{H5S_UNLIMITED}, chunk;
  hsize_t chunk_frames = kScalarChunkFrames;
  if (!frame_shape.empty()) {
    std::size_t row = std::max<std::size_t>(c.row_bytes, 1);
    chunk_frames = std::clamp<hsize_t>(kChunkBytes / row, 1, kMaxChunkFrames);
  }
  chunk.push_back(chunk_frames);
  c.chunk_rows = static_cast<std::size_t>(chunk_frames);
  for (hsize_t d : frame_shape) {
    dims.push_back(d);
    // a zero extent (mesh without points) cannot be chunked as fixed: leave it open
    max_dims.push_back(d == 0 ? H5S_UNLIMITED : d);
    chunk.push_back(std::max<hsize_t>(d, 1));
  }
  const std::string what = "create data set '" + name + "'";
  h5::Handle space(h5::check_id(
      H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max_dims.data()), what));
  h5::Handle dcpl(h5::check_id(H5Pcreate(H5P_DATASET_CREATE), what));
  h5::check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), what);
  // HDF5 keeps no checksum on raw data unless asked: with Fletcher32 a damaged chunk fails to
  // read instead of returning altered numbers (a built-in filter, every HDF5 reader has it)
  h5::check(H5Pset_fletcher32(dcpl.get()), what);
  h5::check(H5Pset_obj_track_times(dcpl.get(), 0), what);
  // rows past frames_written (never announced) read as NaN / -1, not as plausible zeros
  if (fill) h5::check(H5Pset_fill_value(dcpl.get(), mem_type, fill), what);
  c.dset = h5::Handle(h5::check_id(
      H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      what));
  if (!description.empty()) h5::write_attr_string(c.dset.get(), "description", description);
  h5::write_attr_string(c.dset.get(), "unit", unit);
  return c;
}

// a name that becomes an HDF5 link: non-empty, no '/', not "." or "..", unique
std::string check_names(const std::vector<Quantity>& quantities, const char* kind) {
  std::set<std::string> seen;
  for (const auto& q : quantities) {
    if (q.name.empty()) return std::string(kind) + " with an empty name";
    if (q.name.find('/') != std::string::npos || q.name == "." || q.name == "..") {
      return std::string(kind) + " name '" + q.name + "' is not a valid data set name" +
             (q.name.find('/') != std::string::npos ? " (contains '/')" : "");
    }
    if (!seen.insert(q.name).second) return std::string(kind) + " name '" + q.name + "' is repeated";
  }
  return {};
}

std::string check_indices(const std::vector<std::int32_t>& indices, std::size_t per_cell,
                          std::size_t point_count, const char* kind) {
  if (indices.size() % per_cell != 0) {
    return std::string("mesh ") + kind + " has " + std::to_string(indices.size()) +
           " indices, not a multiple of " + std::to_string(per_cell);
  }
  for (std::int32_t i : indices) {
    if (i < 0 || static_cast<std::size_t>(i) >= point_count) {
      return std::string("mesh ") + kind + " refer to point " + std::to_string(i) + " of " +
             std::to_string(point_count);
    }
  }
  return {};
}

}  // namespace

std::string file_names_problem(const RunInfo& info) {
  if (!info.scene_name.empty())
    if (const std::string why = file_name_problem(info.scene_name); !why.empty())
      return "the scene name '" + info.scene_name + "' " + why + ", so it cannot name an output file";
  for (const Quantity& q : info.probes)
    if (const std::string why = file_name_problem(q.name); !why.empty())
      return "the probe name '" + q.name + "' " + why + ", so it cannot name its plot file";
  return "";
}

namespace {

std::string validate(const RunInfo& info) {
  const FrameMesh& m = info.mesh;
  if (m.reference_points.size() % 3 != 0) {
    return "mesh has " + std::to_string(m.reference_points.size()) +
           " reference coordinates, not a multiple of 3";
  }
  std::size_t n = m.point_count();
  for (const std::string& e : {check_indices(m.lines, 2, n, "lines"),
                               check_indices(m.triangles, 3, n, "triangles"),
                               check_indices(m.quads, 4, n, "quads"),
                               check_names(info.probes, "probe"), check_names(info.fields, "field"),
                               file_names_problem(info)}) {
    if (!e.empty()) return e;
  }
  for (const auto& [key, value] : info.settings) {
    if (key.empty()) return "a setting has an empty key";
  }
  return {};
}

// H5Fcreate(H5F_ACC_TRUNC) truncates before it takes HDF5's flock, so a second run started
// on the same path would wipe the live file of the first. Probe the lock first.
std::string locked_by_another_process(const std::string& path) {
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) return {};  // absent (or unreadable: H5Fcreate will say why)
  std::string why;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) {
      why = "the file is open in another process (is a run still writing it?); not overwritten";
    }
  } else {
    ::flock(fd, LOCK_UN);
  }
  ::close(fd);
  return why;
}

}  // namespace

namespace {

// An upper bound of the bytes create() writes: the run description (mesh, scene text, names and
// settings) and, per data set it creates, its object header and first index node.
std::uint64_t run_info_bytes_bound(const RunInfo& info) {
  constexpr std::uint64_t kPerObjectBytes = 4096;
  const FrameMesh& m = info.mesh;
  std::uint64_t bytes = 8 * m.reference_points.size() + 4 * (m.lines.size() + m.triangles.size() + m.quads.size()) +
                        info.scene_text.size() + info.scene_name.size() + info.scene_path.size();
  for (const auto& [key, value] : info.settings) bytes += key.size() + value.size() + 64;
  std::uint64_t objects = 32 + info.effects.size();  // groups, fixed columns, the step log
  for (const std::vector<Quantity>* qs : {&info.probes, &info.fields}) {
    objects += qs->size();
    for (const Quantity& q : *qs) bytes += q.name.size() + q.unit.size() + q.label.size();
  }
  return bytes + objects * kPerObjectBytes + kMetadataMarginBytes;
}

// How the writer opens its file (created or amended): locked against a second writer, but working
// on file systems without flock; closing the file closes whatever is still open in it, so a failed
// write never leaves objects for HDF5's exit handler to close after the file has gone
h5::Handle writer_file_access() {
  h5::Handle fapl(h5::check_id(H5Pcreate(H5P_FILE_ACCESS), "file access properties"));
#if H5_VERSION_GE(1, 10, 7)
  h5::check(H5Pset_file_locking(fapl.get(), 1, 1), "file access properties");
#endif
  h5::check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "file access properties");
  return fapl;
}

// "disk full: ..." when the folder of `path` has less room than create() may need, or ""
std::string room_for_run_info(const std::string& path, const RunInfo& info) {
  const std::uint64_t need = run_info_bytes_bound(info);
  struct statvfs disk {};
  const std::string folder = std::filesystem::path(path).parent_path().string();
  if (::statvfs(folder.empty() ? "." : folder.c_str(), &disk) != 0) return "";  // H5Fcreate says why
  const std::uint64_t free_bytes = static_cast<std::uint64_t>(disk.f_bavail) * disk.f_frsize;
  if (free_bytes >= need) return "";
  return "disk full: " + std::to_string(free_bytes / 1024) + " KiB free, the run's description (its mesh and scene) "
         "needs up to " + std::to_string(need / 1024) + " KiB; nothing was written";
}

}  // namespace

/// Writes the `count` staged rows of each column at row `first` (extents are absolute, so a
/// retry after a failed flush is harmless).
// An upper bound of the file space that writing rows [first, first + count) may take: every
// chunk those rows touch, whole (a filtered chunk that changes may be moved, not rewritten in place).
std::uint64_t rows_bytes_bound(const std::vector<Column>& columns, std::size_t first, std::size_t count) {
  if (count == 0) return 0;
  std::uint64_t bytes = 0;
  for (const Column& c : columns) {
    const std::size_t chunks = (first + count - 1) / c.chunk_rows - first / c.chunk_rows + 1;
    bytes += static_cast<std::uint64_t>(chunks) * c.chunk_rows * std::max<std::size_t>(c.row_bytes, 1);
  }
  return bytes;
}

void write_rows(std::vector<Column>& columns, std::size_t first_row, std::size_t count_rows, const char* what_rows) {
  if (count_rows == 0) return;
  const hsize_t first = first_row, count = count_rows, total = first + count;
  for (Column& c : columns) {
    const std::string what = "write " + std::to_string(count) + " " + what_rows + " to '" + c.name + "'";
    std::vector<hsize_t> dims{total}, start{first}, shape{count};
    for (hsize_t d : c.frame_shape) {
      dims.push_back(d);
      start.push_back(0);
      shape.push_back(d);
    }
    h5::check(H5Dset_extent(c.dset.get(), dims.data()), what);
    if (c.row_bytes == 0) continue;
    h5::Handle fspace(h5::check_id(H5Dget_space(c.dset.get()), what));
    h5::check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, shape.data(), nullptr), what);
    h5::Handle mspace(
        h5::check_id(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), what));
    h5::check(H5Dwrite(c.dset.get(), c.mem_type, mspace.get(), fspace.get(), H5P_DEFAULT, c.staged.data()), what);
  }
}

struct ResultWriter::Impl {
  std::string path;
  h5::Handle file;  // first member: released last
  h5::Handle bool_type;
  h5::Handle frames_group, outcome_group, metrics_group, attributes_group;

  // fixed columns, then one per probe, one per field, and the checksum last
  enum : std::size_t { kTime, kStep, kLoad, kDt, kIter, kJac, kRes, kInc, kConv, kPoints, kBase,
                       kFixed };
  std::size_t checksum_column = 0;
  std::vector<Column> columns;
  // the per-step convergence log: its own rows, announced by /steps steps_written
  enum : std::size_t { kLogStep, kLogTime, kLogDt, kLogIter, kLogJac, kLogRes, kLogInc, kLogConv };
  h5::Handle steps_group;
  std::vector<Column> step_columns;
  std::size_t steps_written = 0, steps_staged = 0;
  std::size_t point_count = 0, probe_count = 0, field_count = 0;

  std::size_t frames_written = 0, frames_staged = 0;
  std::vector<std::pair<std::string, std::string>> staged_attributes;
  bool modes_written = false;
  double last_staged_time = 0.0, last_written_time = 0.0;
  std::int64_t last_staged_step = 0, last_written_step = 0;
  Clock::time_point created = Clock::now(), last_flush = Clock::now();
  bool closed = false;

  std::string prefix() const { return "results file '" + path + "': "; }

  void write_run_info(const RunInfo& info);
  void stage_step(std::int64_t step, double time, const StepStats& st);  // one row of /steps
  void create_frame_columns(const RunInfo& info);
  void write_unfinished_outcome();
  void write_progress();
  void flush_or_throw();
  void close_or_throw();
};

void ResultWriter::Impl::write_run_info(const RunInfo& info) {
  hid_t f = file.get();
  h5::write_attr_string(f, "format", names::kFormat);
  h5::write_attr_int64(f, "format_version", names::kFormatVersion);

  h5::Handle run = h5::create_group(f, names::kRun, false);
  h5::write_attr_string(run.get(), "scene_name", info.scene_name);
  h5::write_attr_string(run.get(), "scene_path", info.scene_path);
  h5::write_attr_string(run.get(), "time_unit", info.time_unit);
  h5::write_attr_strings(run.get(), "effects", info.effects);
  h5::write_string_dataset(f, names::kSceneText, info.scene_text);
  h5::Handle settings = h5::create_group(f, names::kSettings, true);
  for (const auto& [key, value] : info.settings) h5::write_attr_string(settings.get(), key, value);

  const FrameMesh& m = info.mesh;
  h5::Handle mesh = h5::create_group(f, names::kMesh, false);
  h5::write_attr_int64(mesh.get(), "point_count", static_cast<std::int64_t>(m.point_count()));
  h5::write_fixed_dataset(mesh.get(), "reference_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                          {m.point_count(), 3}, m.reference_points.data());
  h5::write_fixed_dataset(mesh.get(), "lines", H5T_STD_I32LE, H5T_NATIVE_INT32,
                          {m.lines.size() / 2, 2}, m.lines.data());
  h5::write_fixed_dataset(mesh.get(), "triangles", H5T_STD_I32LE, H5T_NATIVE_INT32,
                          {m.triangles.size() / 3, 3}, m.triangles.data());
  h5::write_fixed_dataset(mesh.get(), "quads", H5T_STD_I32LE, H5T_NATIVE_INT32,
                          {m.quads.size() / 4, 4}, m.quads.data());

  outcome_group = h5::create_group(f, names::kOutcome, true);
  metrics_group = h5::create_group(f, names::kMetrics, true);
  attributes_group = h5::create_group(f, names::kAttributes, true);
  create_frame_columns(info);
  write_unfinished_outcome();
}

void ResultWriter::Impl::create_frame_columns(const RunInfo& info) {
  hid_t f = file.get();
  point_count = info.mesh.point_count();
  probe_count = info.probes.size();
  field_count = info.fields.size();
  bool_type = h5::bool_type();

  frames_group = h5::create_group(f, names::kFrames, false);
  h5::write_attr_int64(frames_group.get(), names::kFramesWritten, 0);
  h5::Handle stats = h5::create_group(f, names::kStats, false);
  h5::Handle probes = h5::create_group(f, names::kProbes, false);
  h5::Handle fields = h5::create_group(f, names::kFields, false);

  const std::string& tu = info.time_unit;
  const hsize_t n = point_count;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::int64_t minus_one_64 = -1;
  const std::int32_t minus_one_32 = -1;
  auto add = [&](hid_t loc, const std::string& name, hid_t file_type, hid_t mem_type,
                 std::size_t bytes, std::vector<hsize_t> shape, const std::string& description,
                 const std::string& unit) {
    const void* fill = mem_type == H5T_NATIVE_DOUBLE  ? static_cast<const void*>(&nan)
                       : mem_type == H5T_NATIVE_INT64 ? static_cast<const void*>(&minus_one_64)
                       : mem_type == H5T_NATIVE_INT32 ? static_cast<const void*>(&minus_one_32)
                                                      : nullptr;
    columns.push_back(
        make_column(loc, name, file_type, mem_type, bytes, shape, description, unit, fill));
  };
  hid_t fr = frames_group.get(), st = stats.get();
  add(fr, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {},
      "simulated time (pseudo-time for statics)", tu);
  add(fr, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, 8, {}, "solver step (0 = initial state)", "");
  add(fr, "load_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {},
      "load factor lambda (statics), 0 where meaningless", "");
  add(st, "dt", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {},
      "step size used (time for dynamics, load for statics)", tu);
  add(st, "iterations", H5T_STD_I32LE, H5T_NATIVE_INT32, 4, {}, "Newton iterations", "");
  add(st, "jacobian_updates", H5T_STD_I32LE, H5T_NATIVE_INT32, 4, {},
      "iteration-matrix factorizations", "");
  add(st, "residual_norm", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "final residual norm", "");
  add(st, "increment_norm", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "final increment norm", "");
  add(st, "converged", bool_type.get(), bool_type.get(), 1, {}, "step converged", "");
  add(fr, "points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {n, 3},
      "current world positions of the mesh points", "");
  add(fr, "base_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {n, 3},
      "undeformed body carried by its rigid motion (points - base_points = deformation)", "");

  std::vector<std::string> order;
  for (const Quantity& q : info.probes) {
    add(probes.get(), q.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "", q.unit);
    h5::write_attr_string(columns.back().dset.get(), "label", q.label);
    order.push_back(q.name);
  }
  h5::write_attr_strings(probes.get(), "names", order);
  order.clear();
  for (const Quantity& q : info.fields) {
    add(fields.get(), q.name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {n}, "", q.unit);
    h5::write_attr_string(columns.back().dset.get(), "label", q.label);
    order.push_back(q.name);
  }
  h5::write_attr_strings(fields.get(), "names", order);
  steps_group = h5::create_group(f, names::kSteps, false);
  h5::write_attr_int64(steps_group.get(), names::kStepsWritten, 0);
  const std::size_t frame_columns = columns.size();
  hid_t sg = steps_group.get();
  add(sg, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, 8, {}, "solver step", "");
  add(sg, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "time (load factor for statics) at the end of the step", tu);
  add(sg, "dt", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "step size", tu);
  add(sg, "iterations", H5T_STD_I32LE, H5T_NATIVE_INT32, 4, {}, "Newton iterations of the step (NOI)", "");
  add(sg, "jacobian_updates", H5T_STD_I32LE, H5T_NATIVE_INT32, 4, {},
      "iteration-matrix factorizations of the step (NOU)", "");
  add(sg, "residual_norm", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "final residual norm", "");
  add(sg, "increment_norm", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 8, {}, "final increment norm", "");
  add(sg, "converged", bool_type.get(), bool_type.get(), 1, {}, "step converged", "");
  step_columns.assign(std::make_move_iterator(columns.begin() + frame_columns), std::make_move_iterator(columns.end()));
  columns.erase(columns.begin() + frame_columns, columns.end());
  checksum_column = columns.size();
  add(fr, "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, 8, {},
      "FNV-1a 64 of the frame's rows of all other frame data sets (see results_layout.md)", "");
}

// written once by create(): what a reader sees unless finish() runs
void ResultWriter::Impl::write_unfinished_outcome() {
  hid_t o = outcome_group.get();
  h5::write_attr_string(o, "status", to_string(RunStatus::interrupted));
  h5::write_attr_string(o, "reason", std::string(names::kUnfinished) +
                                         "; /frames/frames_written tells how many frames were saved");
  h5::write_attr_double(o, "stop_time", 0.0);
  h5::write_attr_int64(o, "steps", 0);
  h5::write_attr_double(o, "wall_time_s", 0.0);
  h5::write_attr_int64(o, "finished", 0);
}

// rewritten by every flush: fixed-size numbers only, overwritten in place
void ResultWriter::Impl::write_progress() {
  h5::write_attr_int64(frames_group.get(), names::kFramesWritten,
                       static_cast<std::int64_t>(frames_written));
  h5::write_attr_int64(steps_group.get(), names::kStepsWritten, static_cast<std::int64_t>(steps_written));
  hid_t o = outcome_group.get();
  h5::write_attr_double(o, "stop_time", last_written_time);
  h5::write_attr_int64(o, "steps", last_written_step);
  h5::write_attr_double(o, "wall_time_s",
                        std::chrono::duration<double>(Clock::now() - created).count());
}

void ResultWriter::Impl::flush_or_throw() {
  if (closed) throw h5::Failure("the file is already closed");
  // HDF5 that meets a full disk in the middle of a write keeps dirty chunks it can neither
  // write nor drop (closing them later fails, and HDF5 1.10 can crash at exit). So a block that
  // might not fit is not handed to HDF5 at all: the file stays as the last flush left it.
  const std::uint64_t need = rows_bytes_bound(columns, frames_written, frames_staged) +
                             rows_bytes_bound(step_columns, steps_written, steps_staged) + kMetadataMarginBytes;
  struct statvfs disk {};
  const std::string folder = std::filesystem::path(path).parent_path().string();
  if (::statvfs(folder.empty() ? "." : folder.c_str(), &disk) == 0) {
    const std::uint64_t free_bytes = static_cast<std::uint64_t>(disk.f_bavail) * disk.f_frsize;
    if (free_bytes < need)
      throw h5::Failure("disk full: " + std::to_string(free_bytes / 1024) + " KiB free, the next " +
                        std::to_string(frames_staged) + " frame(s) need up to " + std::to_string(need / 1024) +
                        " KiB; the file keeps the " + std::to_string(frames_written) + " frame(s) written before");
  }
  write_rows(columns, frames_written, frames_staged, "frames");
  write_rows(step_columns, steps_written, steps_staged, "steps");
  for (const auto& [key, value] : staged_attributes) {
    h5::write_attr_string(attributes_group.get(), key, value);
  }
  // phase 1 makes the data durable; only then does phase 2 announce it in frames_written.
  // HDF5 (without SWMR) writes metadata in no particular order inside one H5Fflush, so a
  // kill during a single combined flush could leave frames_written ahead of the data.
  h5::check(H5Fflush(file.get(), H5F_SCOPE_LOCAL), "flush frame data");
  const std::size_t total = frames_written + frames_staged;
  const std::size_t saved_steps = steps_written;
  steps_written += steps_staged;
  std::size_t saved_written = frames_written;
  double saved_time = last_written_time;
  std::int64_t saved_step = last_written_step;
  frames_written = total;
  if (frames_staged > 0) {
    last_written_time = last_staged_time;
    last_written_step = last_staged_step;
  }
  try {
    write_progress();
    h5::check(H5Fflush(file.get(), H5F_SCOPE_LOCAL), "flush frames_written");
  } catch (...) {
    steps_written = saved_steps;
    frames_written = saved_written;
    last_written_time = saved_time;
    last_written_step = saved_step;
    throw;
  }
  for (Column& c : columns) c.staged.clear();
  for (Column& c : step_columns) c.staged.clear();
  frames_staged = 0;
  steps_staged = 0;
  staged_attributes.clear();
  last_flush = Clock::now();
}

void ResultWriter::Impl::close_or_throw() {
  if (closed) return;
  closed = true;
  columns.clear();
  step_columns.clear();
  steps_group.reset();
  frames_group.reset();
  outcome_group.reset();
  metrics_group.reset();
  attributes_group.reset();
  bool_type.reset();
  h5::check(H5Fclose(file.release()), "close");
}

ResultWriter::ResultWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

std::unique_ptr<ResultWriter> ResultWriter::create(const std::string& path, const RunInfo& info,
                                                   std::string* error) {
  h5::Quiet quiet;
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  const std::string prefix = "cannot create results file '" + path + "': ";
  if (std::string why = validate(info); !why.empty()) {
    if (error) *error = prefix + why;
    return nullptr;
  }
  // HDF5 opens by name and would follow a link: what is there must be a file of its own
  if (std::string why = output_entry_problem(path); !why.empty()) {
    if (error) *error = prefix + why + "; nothing was written through it";
    return nullptr;
  }
  if (std::string why = locked_by_another_process(path); !why.empty()) {
    if (error) *error = prefix + why;
    return nullptr;
  }
  // the same rule as every flush (flush_or_throw): what might not fit is not handed to HDF5, which
  // cannot drop what it failed to write (a file it could not create crashed its exit handler)
  if (std::string why = room_for_run_info(path, info); !why.empty()) {
    if (error) *error = prefix + why;
    return nullptr;
  }
  try {
    const h5::Handle fapl = writer_file_access();
    impl->file = h5::Handle(
        h5::check_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), ""));
    impl->write_run_info(info);
    h5::check(H5Fflush(impl->file.get(), H5F_SCOPE_LOCAL), "flush");
  } catch (const h5::Failure& e) {
    if (error) *error = prefix + e.what();
    impl->closed = true;  // handles are released by ~Impl
    return nullptr;
  }
  impl->created = impl->last_flush = Clock::now();
  return std::unique_ptr<ResultWriter>(new ResultWriter(std::move(impl)));
}

bool ResultWriter::append(const Frame& frame, std::string* error) {
  Impl& m = *impl_;
  auto bad = [&](const std::string& why) {
    if (error) *error = m.prefix() + why;
    return false;
  };
  if (m.closed) return bad("append after finish()");
  const std::string at = "frame of step " + std::to_string(frame.step) + ": ";
  const std::size_t n = m.point_count;
  if (frame.points.size() != 3 * n) {
    return bad(at + "points has " + std::to_string(frame.points.size()) + " values, expected 3 x " +
               std::to_string(n));
  }
  if (frame.base_points.size() != 3 * n) {
    return bad(at + "base_points has " + std::to_string(frame.base_points.size()) +
               " values, expected 3 x " + std::to_string(n));
  }
  if (frame.probes.size() != m.probe_count) {
    return bad(at + std::to_string(frame.probes.size()) + " probe values, expected " +
               std::to_string(m.probe_count));
  }
  if (frame.fields.size() != m.field_count) {
    return bad(at + std::to_string(frame.fields.size()) + " fields, expected " +
               std::to_string(m.field_count));
  }
  for (std::size_t k = 0; k < m.field_count; ++k) {
    if (frame.fields[k].size() != n) {
      return bad(at + "field '" + m.columns[Impl::kFixed + m.probe_count + k].name + "' has " +
                 std::to_string(frame.fields[k].size()) + " values, expected " + std::to_string(n));
    }
  }

  const StepStats& s = frame.stats;
  const std::int8_t converged = s.converged ? 1 : 0;
  auto& c = m.columns;
  // columns in their creation order, which is also the checksum order
  std::uint64_t checksum = kFnvOffset;
  auto stage = [&](std::size_t column, const void* row) {
    c[column].stage(row);
    checksum = fnv1a(checksum, row, c[column].row_bytes);
  };
  stage(Impl::kTime, &frame.time);
  stage(Impl::kStep, &frame.step);
  stage(Impl::kLoad, &frame.load_factor);
  stage(Impl::kDt, &s.dt);
  stage(Impl::kIter, &s.iterations);
  stage(Impl::kJac, &s.jacobian_updates);
  stage(Impl::kRes, &s.residual_norm);
  stage(Impl::kInc, &s.increment_norm);
  stage(Impl::kConv, &converged);
  stage(Impl::kPoints, frame.points.data());
  stage(Impl::kBase, frame.base_points.data());
  for (std::size_t k = 0; k < m.probe_count; ++k) stage(Impl::kFixed + k, &frame.probes[k]);
  for (std::size_t k = 0; k < m.field_count; ++k) {
    stage(Impl::kFixed + m.probe_count + k, frame.fields[k].data());
  }
  c[m.checksum_column].stage(&checksum);
  ++m.frames_staged;
  // the convergence log: the frame's steps, or the frame itself when it is one solver step
  if (!frame.step_log.empty()) {
    for (const StepRecord& r : frame.step_log) m.stage_step(r.step, r.time, r.stats);
  } else if (frame.step > 0) {
    m.stage_step(frame.step, frame.time, frame.stats);
  }
  m.last_staged_time = frame.time;
  m.last_staged_step = frame.step;

  const double since_flush_s = std::chrono::duration<double>(Clock::now() - m.last_flush).count();
  if (m.frames_staged >= kFlushFrames || since_flush_s >= kFlushSeconds) {
    std::string why;
    if (!flush(&why)) {
      if (error) *error = why + " (the frame is kept in memory and retried at the next flush)";
      return false;
    }
  }
  return true;
}

void ResultWriter::Impl::stage_step(std::int64_t step, double time, const StepStats& st) {
  const std::int8_t conv = st.converged ? 1 : 0;
  auto& l = step_columns;
  l[kLogStep].stage(&step);
  l[kLogTime].stage(&time);
  l[kLogDt].stage(&st.dt);
  l[kLogIter].stage(&st.iterations);
  l[kLogJac].stage(&st.jacobian_updates);
  l[kLogRes].stage(&st.residual_norm);
  l[kLogInc].stage(&st.increment_norm);
  l[kLogConv].stage(&conv);
  ++steps_staged;
}

void ResultWriter::set_attribute(const std::string& key, const std::string& value) {
  if (key.empty()) return;
  for (auto& [k, v] : impl_->staged_attributes) {
    if (k == key) {
      v = value;
      return;
    }
  }
  impl_->staged_attributes.emplace_back(key, value);
}

bool ResultWriter::write_modes(const ModeSet& modes, std::string* error) {
  h5::Quiet quiet;
  Impl& m = *impl_;
  auto bad = [&](const std::string& why) {
    if (error) *error = m.prefix() + why;
    return false;
  };
  if (m.closed) return bad("modes written after finish()");
  if (m.modes_written) return bad("the modes were already written");
  const std::size_t n = m.point_count, count = modes.modes.size();
  for (const Mode& mode : modes.modes)
    if (mode.displacement.size() != 3 * n)
      return bad("mode " + std::to_string(mode.number) + " has " + std::to_string(mode.displacement.size()) +
                 " displacement values, expected 3 x " + std::to_string(n));
  std::vector<std::int64_t> numbers;
  std::vector<double> values, eigenvalues, displacement;
  std::vector<std::int8_t> rigid;
  displacement.reserve(3 * n * count);
  for (const Mode& mode : modes.modes) {
    numbers.push_back(mode.number);
    values.push_back(mode.value);
    eigenvalues.push_back(mode.eigenvalue);
    rigid.push_back(mode.rigid_body ? 1 : 0);
    displacement.insert(displacement.end(), mode.displacement.begin(), mode.displacement.end());
  }
  try {
    hid_t f = m.file.get();
    h5::Handle g = h5::create_group(f, names::kModes, false);
    h5::write_attr_string(g.get(), "analysis", modes.analysis);
    h5::write_attr_string(g.get(), "about", modes.about);
    h5::write_attr_string(g.get(), "value_name", modes.value_name);
    h5::write_attr_string(g.get(), "value_unit", modes.value_unit);
    h5::write_attr_string(g.get(), "value_label", modes.value_label);
    h5::write_attr_int64(g.get(), "count", static_cast<std::int64_t>(count));
    const hsize_t rows = count;
    h5::write_fixed_dataset(g.get(), "number", H5T_STD_I64LE, H5T_NATIVE_INT64, {rows}, numbers.data());
    h5::write_fixed_dataset(g.get(), "value", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows}, values.data());
    h5::write_fixed_dataset(g.get(), "eigenvalue", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows}, eigenvalues.data());
    h5::write_fixed_dataset(g.get(), "rigid_body", m.bool_type.get(), m.bool_type.get(), {rows}, rigid.data());
    h5::write_fixed_dataset(g.get(), "displacement", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows, n, 3},
                            displacement.data());
    h5::check(H5Fflush(f, H5F_SCOPE_LOCAL), "flush the modes");
  } catch (const h5::Failure& e) {
    return bad(e.what());
  }
  m.modes_written = true;
  return true;
}

bool ResultWriter::write_twin_history(const std::string& twin, const std::string& description,
                                      const std::vector<double>& time, const std::vector<std::string>& probe_names,
                                      const std::vector<std::vector<double>>& probes, std::string* error) {
  h5::Quiet quiet;
  Impl& m = *impl_;
  auto bad = [&](const std::string& why) {
    if (error) *error = m.prefix() + why;
    return false;
  };
  if (m.closed) return bad("a twin's history written after finish()");
  const bool plain = !twin.empty() && std::all_of(twin.begin(), twin.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
  if (!plain) return bad("twin name '" + twin + "' is not a plain name");
  if (probe_names.size() != probes.size()) return bad("twin " + twin + ": probe names and series differ in count");
  for (std::size_t k = 0; k < probes.size(); ++k)
    if (probes[k].size() != time.size() || probe_names[k].empty() || probe_names[k].find('/') != std::string::npos)
      return bad("twin " + twin + ": probe '" + probe_names[k] + "' has no valid name or not one value per frame");
  try {
    hid_t f = m.file.get();
    h5::Handle all = h5::has_link(f, names::kErrorBarTwins) ? h5::open_group(f, names::kErrorBarTwins)
                                                             : h5::create_group(f, names::kErrorBarTwins, false);
    h5::Handle g = h5::create_group(all.get(), twin, false);
    h5::write_attr_string(g.get(), "description", description);
    const hsize_t rows = time.size();
    h5::write_fixed_dataset(g.get(), "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows}, time.data());
    h5::Handle p = h5::create_group(g.get(), "probes", false);
    for (std::size_t k = 0; k < probes.size(); ++k)
      h5::write_fixed_dataset(p.get(), probe_names[k], H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {rows}, probes[k].data());
    h5::check(H5Fflush(f, H5F_SCOPE_LOCAL), "flush the twin's history");
  } catch (const h5::Failure& e) {
    return bad(e.what());
  }
  return true;
}

bool ResultWriter::flush(std::string* error) {
  h5::Quiet quiet;
  try {
    impl_->flush_or_throw();
  } catch (const h5::Failure& e) {
    if (error) *error = impl_->prefix() + e.what();
    return false;
  }
  return true;
}

bool ResultWriter::finish(const RunOutcome& outcome,
                          const std::vector<std::pair<std::string, double>>& metrics,
                          std::string* error) {
  h5::Quiet quiet;
  Impl& m = *impl_;
  if (m.closed) {
    if (error) *error = m.prefix() + "finish() after the file was closed";
    return false;
  }
  std::string skipped, flush_failure;
  try {
    // the attempts the run ended on belong to no frame: their rows close the convergence log
    for (const StepRecord& r : outcome.trailing_attempts) m.stage_step(r.step, r.time, r.stats);
    // frames that cannot be stored (a full disk) must not keep the outcome from being recorded
    try {
      m.flush_or_throw();
    } catch (const h5::Failure& e) {
      flush_failure = e.what();
    }
    for (const auto& [name, value] : metrics) {
      if (name.empty()) {
        skipped = "a metric with an empty name was not stored";
        continue;
      }
      h5::write_attr_double(m.metrics_group.get(), name, value);
    }
    hid_t o = m.outcome_group.get();
    // frames that could not be stored make the run failed, in the file as in summary.json
    const bool lost_frames = !flush_failure.empty() && outcome.status != RunStatus::failed;
    h5::write_attr_string(o, "status", to_string(lost_frames ? RunStatus::failed : outcome.status));
    h5::write_attr_string(o, "reason", lost_frames ? "an output could not be written: results.h5: " + flush_failure +
                                                         " (the frames after the last flush are not stored)"
                                                   : outcome.reason);
    h5::write_attr_double(o, "stop_time", outcome.stop_time);
    h5::write_attr_int64(o, "steps", outcome.steps);
    if (outcome.cutbacks >= 0) h5::write_attr_int64(o, "cutbacks", outcome.cutbacks);
    h5::write_attr_double(o, "wall_time_s", outcome.wall_time_s);
    if (!outcome.events.empty()) {  // the path's events, one entry each (results_layout.md)
      std::vector<std::string> kinds, details;
      std::vector<double> steps, loads;
      for (const PathEvent& e : outcome.events) {
        kinds.push_back(e.kind);
        details.push_back(e.detail);
        steps.push_back(static_cast<double>(e.step));
        loads.push_back(e.load_factor);
      }
      h5::write_attr_strings(o, "event_kind", kinds);
      h5::write_attr_doubles(o, "event_step", steps);
      h5::write_attr_doubles(o, "event_load_factor", loads);
      h5::write_attr_strings(o, "event_detail", details);
    }
    // "finished" goes last, after everything it vouches for is on disk
    h5::check(H5Fflush(m.file.get(), H5F_SCOPE_LOCAL), "flush the outcome");
    h5::write_attr_int64(o, "finished", 1);
    m.close_or_throw();
  } catch (const h5::Failure& e) {
    if (error) *error = m.prefix() + e.what();
    try {
      m.close_or_throw();
    } catch (const h5::Failure&) {
    }
    return false;
  }
  if (!flush_failure.empty()) {
    if (error)
      *error = m.prefix() + flush_failure + " (the outcome is recorded; the " + std::to_string(m.frames_staged) +
               " frame(s) after the last flush are not)";
    return false;
  }
  if (!skipped.empty()) {
    if (error) *error = m.prefix() + skipped;
    return false;
  }
  return true;
}

bool amend_outcome(const std::string& path, const RunOutcome& outcome, std::string* error) {
  h5::Quiet quiet;
  try {
    const h5::Handle fapl = writer_file_access();
    h5::Handle file(h5::check_id(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), "open"));
    {
      h5::Handle o = h5::open_group(file.get(), names::kOutcome);
      h5::write_attr_string(o.get(), "status", to_string(outcome.status));
      h5::write_attr_string(o.get(), "reason", outcome.reason);
    }
    h5::check(H5Fclose(file.release()), "close");
  } catch (const h5::Failure& e) {
    if (error) *error = "cannot update the outcome of results file '" + path + "': " + e.what();
    return false;
  }
  return true;
}

std::size_t ResultWriter::frames_appended() const {
  return impl_->frames_written + impl_->frames_staged;
}

std::size_t ResultWriter::frames_flushed() const { return impl_->frames_written; }

const std::string& ResultWriter::path() const { return impl_->path; }

ResultWriter::~ResultWriter() {
  if (!impl_ || impl_->closed) return;
  h5::Quiet quiet;
  // best effort: what was flushed stays readable even if this fails
  try {
    impl_->flush_or_throw();
  } catch (const h5::Failure&) {
  }
  try {
    impl_->close_or_throw();
  } catch (const h5::Failure&) {
  }
}

}  // namespace ff::io
