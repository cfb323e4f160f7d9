/// \file result_reader.cpp
/// ResultReader: opens results.h5 (finished, interrupted or killed), reads the constant parts
/// at open and frame data on demand. Trusts frames_written, never the raw data set extents.

#include <algorithm>
#include <bit>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "app/io/frame_checksum.h"
#include "app/io/h5_util.h"
#include "app/io/results.h"
#include "app/io/results_names.h"

namespace ff::io {

namespace {

static_assert(std::endian::native == std::endian::little, "checksums hash little-endian rows");

RunStatus parse_status(const std::string& s, bool* known) {
  *known = true;
  for (RunStatus r : {RunStatus::completed, RunStatus::incomplete, RunStatus::diverged, RunStatus::interrupted,
                      RunStatus::failed}) {
    if (s == to_string(r)) return r;
  }
  *known = false;
  return RunStatus::failed;
}

std::vector<Quantity> read_quantities(hid_t group) {
  std::vector<Quantity> out;
  for (const std::string& name : h5::read_attr_strings(group, "names")) {
    h5::Handle d = h5::open_dataset(group, name);
    Quantity q;
    q.name = name;
    if (h5::has_attr(d.get(), "unit")) q.unit = h5::read_attr_string(d.get(), "unit");
    if (h5::has_attr(d.get(), "label")) q.label = h5::read_attr_string(d.get(), "label");
    out.push_back(std::move(q));
  }
  return out;
}

template <class T>
std::vector<T> read_matrix(hid_t loc, const std::string& name, hid_t mem_type) {
  h5::Handle d = h5::open_dataset(loc, name);
  hsize_t n = 1;
  for (hsize_t e : h5::dataset_dims(d.get())) n *= e;
  std::vector<T> out(static_cast<std::size_t>(n));
  if (n > 0) {
    h5::check(H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
              "read data set '" + std::string(names::kMesh) + "/" + name + "'");
  }
  return out;
}

// first bytes of every HDF5 file (when the superblock is at offset 0)
bool has_hdf5_signature(const std::string& path) {
  static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::ifstream in(path, std::ios::binary);
  char head[8] = {0};
  in.read(head, 8);
  return in.gcount() == 8 && std::equal(head, head + 8, kSignature);
}

}  // namespace

struct ResultReader::Impl {
  std::string path;
  h5::Handle file;  // first member: released last
  RunInfo info;
  std::size_t frame_count = 0;
  RunOutcome outcome;
  std::vector<std::pair<std::string, double>> metrics;
  std::vector<std::pair<std::string, std::string>> attributes;

  h5::Handle time, step, load, dt, iterations, jacobian_updates, residual, increment, converged;
  h5::Handle converged_mem_type;  // the file's enum as a native type, or invalid (plain int)
  h5::Handle points, base_points;
  std::vector<h5::Handle> probes, fields;
  h5::Handle checksum;  // invalid in files without one
  std::size_t damaged_frames = 0;  // announced by frames_written but failing their checksum

  /// A frame data set in checksum order, with the memory type and bytes of one row.
  struct ColumnRef {
    const h5::Handle* dset;
    hid_t mem_type;
    std::size_t row_bytes;
  };
  std::vector<ColumnRef> checksum_order() const;
  std::size_t count_verified_frames(std::size_t announced) const;
  void load_all();
  std::string what(const std::string& s) const { return "results file '" + path + "': " + s; }

  template <class T>
  std::vector<T> column(const h5::Handle& d, hid_t mem_type, const char* name) const {
    std::vector<T> out(frame_count);
    h5::read_rows(d.get(), mem_type, 0, frame_count, out.data(), what(std::string("read ") + name));
    return out;
  }
};

void ResultReader::Impl::load_all() {
  hid_t f = file.get();
  if (!h5::has_attr(f, "format") || h5::read_attr_string(f, "format") != names::kFormat ||
      !h5::has_link(f, names::kRun)) {
    throw h5::Failure("an HDF5 file, but not a FlexFrame results file (no 'format' = '" +
                      std::string(names::kFormat) + "' root attribute)");
  }
  std::int64_t version = h5::read_attr_int64(f, "format_version");
  if (version > names::kFormatVersion) {
    throw h5::Failure("format version " + std::to_string(version) +
                      " is newer than this program reads (" +
                      std::to_string(names::kFormatVersion) + ")");
  }

  // run description
  h5::Handle run = h5::open_group(f, names::kRun);
  info.scene_name = h5::read_attr_string(run.get(), "scene_name");
  info.scene_path = h5::read_attr_string(run.get(), "scene_path");
  info.time_unit = h5::read_attr_string(run.get(), "time_unit");
  info.effects = h5::read_attr_strings(run.get(), "effects");
  info.scene_text = h5::read_string_dataset(f, names::kSceneText);
  h5::Handle settings = h5::open_group(f, names::kSettings);
  for (const std::string& key : h5::attr_names(settings.get())) {
    info.settings.emplace_back(key, h5::read_attr_string(settings.get(), key));
  }
  h5::Handle mesh = h5::open_group(f, names::kMesh);
  info.mesh.reference_points = read_matrix<double>(mesh.get(), "reference_points", H5T_NATIVE_DOUBLE);
  info.mesh.lines = read_matrix<std::int32_t>(mesh.get(), "lines", H5T_NATIVE_INT32);
  info.mesh.triangles = read_matrix<std::int32_t>(mesh.get(), "triangles", H5T_NATIVE_INT32);
  info.mesh.quads = read_matrix<std::int32_t>(mesh.get(), "quads", H5T_NATIVE_INT32);

  // frame data sets
  h5::Handle frames = h5::open_group(f, names::kFrames);
  time = h5::open_dataset(frames.get(), "time");
  step = h5::open_dataset(frames.get(), "step");
  load = h5::open_dataset(frames.get(), "load_factor");
  points = h5::open_dataset(frames.get(), "points");
  base_points = h5::open_dataset(frames.get(), "base_points");
  h5::Handle stats = h5::open_group(f, names::kStats);
  dt = h5::open_dataset(stats.get(), "dt");
  iterations = h5::open_dataset(stats.get(), "iterations");
  jacobian_updates = h5::open_dataset(stats.get(), "jacobian_updates");
  residual = h5::open_dataset(stats.get(), "residual_norm");
  increment = h5::open_dataset(stats.get(), "increment_norm");
  converged = h5::open_dataset(stats.get(), "converged");
  {
    h5::Handle t(h5::check_id(H5Dget_type(converged.get()), "type of stats/converged"));
    if (H5Tget_class(t.get()) == H5T_ENUM) {
      converged_mem_type =
          h5::Handle(h5::check_id(H5Tget_native_type(t.get(), H5T_DIR_DEFAULT), "stats/converged"));
      if (H5Tget_size(converged_mem_type.get()) != 1) {
        throw h5::Failure("stats/converged is not a one-byte enum");
      }
    }
  }
  h5::Handle probe_group = h5::open_group(f, names::kProbes);
  info.probes = read_quantities(probe_group.get());
  for (const Quantity& q : info.probes) probes.push_back(h5::open_dataset(probe_group.get(), q.name));
  h5::Handle field_group = h5::open_group(f, names::kFields);
  info.fields = read_quantities(field_group.get());
  for (const Quantity& q : info.fields) fields.push_back(h5::open_dataset(field_group.get(), q.name));

  // complete frames: frames_written of the last flush, never more than any data set holds
  std::vector<const h5::Handle*> all{&time, &step, &load, &points, &base_points, &dt, &iterations,
                                     &jacobian_updates, &residual, &increment, &converged};
  for (const auto& h : probes) all.push_back(&h);
  for (const auto& h : fields) all.push_back(&h);
  hsize_t rows = h5::has_attr(frames.get(), names::kFramesWritten)
                     ? static_cast<hsize_t>(
                           std::max<std::int64_t>(0, h5::read_attr_int64(frames.get(),
                                                                          names::kFramesWritten)))
                     : ~hsize_t{0};
  for (const h5::Handle* h : all) rows = std::min(rows, h5::dataset_dims(h->get()).at(0));
  frame_count = static_cast<std::size_t>(rows);
  const std::size_t n = info.mesh.point_count();
  for (const h5::Handle* h : {&points, &base_points}) {
    auto dims = h5::dataset_dims(h->get());
    if (dims.size() != 3 || dims[1] != n || dims[2] != 3) {
      throw h5::Failure("frames/points or frames/base_points is not (frames x " +
                        std::to_string(n) + " x 3)");
    }
  }
  for (const auto& h : fields) {
    auto dims = h5::dataset_dims(h.get());
    if (dims.size() != 2 || dims[1] != n) {
      throw h5::Failure("a field data set is not (frames x " + std::to_string(n) + ")");
    }
  }

  if (h5::has_link(frames.get(), "checksum")) checksum = h5::open_dataset(frames.get(), "checksum");

  h5::Handle o = h5::open_group(f, names::kOutcome);
  const bool finished =
      h5::has_attr(o.get(), "finished") && h5::read_attr_int64(o.get(), "finished") == 1;
  if (finished) {
    std::string status = h5::read_attr_string(o.get(), "status");
    bool known = false;
    outcome.status = parse_status(status, &known);
    outcome.reason = h5::has_attr(o.get(), "reason") ? h5::read_attr_string(o.get(), "reason") : "";
    if (!known) outcome.reason = "unknown status '" + status + "' in the file; " + outcome.reason;
    outcome.stop_time = h5::read_attr_double(o.get(), "stop_time");
    outcome.steps = h5::read_attr_int64(o.get(), "steps");
    outcome.wall_time_s = h5::read_attr_double(o.get(), "wall_time_s");
    if (h5::has_attr(o.get(), "event_kind")) {
      const std::vector<std::string> kinds = h5::read_attr_strings(o.get(), "event_kind");
      const std::vector<std::string> details = h5::read_attr_strings(o.get(), "event_detail");
      const std::vector<double> steps = h5::read_attr_doubles(o.get(), "event_step");
      const std::vector<double> loads = h5::read_attr_doubles(o.get(), "event_load_factor");
      if (details.size() != kinds.size() || steps.size() != kinds.size() || loads.size() != kinds.size())
        throw h5::Failure("the outcome's event attributes have different lengths");
      for (std::size_t k = 0; k < kinds.size(); ++k)
        outcome.events.push_back({kinds[k], static_cast<std::int64_t>(steps[k]), loads[k], details[k]});
    }
  } else {
    // the writer was stopped: keep only frames whose checksum proves them complete, and take
    // the outcome from the last of them; the stored progress attributes are a fallback only
    if (checksum.valid()) {
      const std::size_t announced = frame_count;
      frame_count = count_verified_frames(announced);
      damaged_frames = announced - frame_count;
    }
    outcome.status = RunStatus::interrupted;
    outcome.reason = std::string(names::kUnfinished) + "; " + std::to_string(frame_count) +
                     " frames were saved";
    if (damaged_frames > 0) {
      outcome.reason += "; " + std::to_string(damaged_frames) +
                        " more were damaged by the interruption and dropped";
    }
    try {
      outcome.wall_time_s = h5::read_attr_double(o.get(), "wall_time_s");
    } catch (const h5::Failure&) {
    }
    if (frame_count > 0) {
      h5::read_rows(time.get(), H5T_NATIVE_DOUBLE, frame_count - 1, 1, &outcome.stop_time,
                    "read the last frame time");
      h5::read_rows(step.get(), H5T_NATIVE_INT64, frame_count - 1, 1, &outcome.steps,
                    "read the last frame step");
    }
  }

  // metrics and attributes: an interrupted writer may have been stopped while adding them
  try {
    if (h5::has_link(f, names::kMetrics)) {
      h5::Handle g = h5::open_group(f, names::kMetrics);
      for (const std::string& key : h5::attr_names(g.get())) {
        metrics.emplace_back(key, h5::read_attr_double(g.get(), key));
      }
    }
    if (h5::has_link(f, names::kAttributes)) {
      h5::Handle g = h5::open_group(f, names::kAttributes);
      for (const std::string& key : h5::attr_names(g.get())) {
        attributes.emplace_back(key, h5::read_attr_string(g.get(), key));
      }
    }
  } catch (const h5::Failure&) {
    if (finished) throw;
  }
}

std::vector<ResultReader::Impl::ColumnRef> ResultReader::Impl::checksum_order() const {
  const std::size_t n = info.mesh.point_count();
  hid_t conv = converged_mem_type.valid() ? converged_mem_type.get() : H5T_NATIVE_INT8;
  std::vector<ColumnRef> cols{{&time, H5T_NATIVE_DOUBLE, 8},
                              {&step, H5T_NATIVE_INT64, 8},
                              {&load, H5T_NATIVE_DOUBLE, 8},
                              {&dt, H5T_NATIVE_DOUBLE, 8},
                              {&iterations, H5T_NATIVE_INT32, 4},
                              {&jacobian_updates, H5T_NATIVE_INT32, 4},
                              {&residual, H5T_NATIVE_DOUBLE, 8},
                              {&increment, H5T_NATIVE_DOUBLE, 8},
                              {&converged, conv, 1},
                              {&points, H5T_NATIVE_DOUBLE, 24 * n},
                              {&base_points, H5T_NATIVE_DOUBLE, 24 * n}};
  for (const auto& h : probes) cols.push_back({&h, H5T_NATIVE_DOUBLE, 8});
  for (const auto& h : fields) cols.push_back({&h, H5T_NATIVE_DOUBLE, 8 * n});
  return cols;
}

// the first frame (from 0) that cannot be read or fails its checksum ends the run
std::size_t ResultReader::Impl::count_verified_frames(std::size_t announced) const {
  const std::vector<ColumnRef> cols = checksum_order();
  std::size_t frame_bytes = 8;
  for (const auto& c : cols) frame_bytes += c.row_bytes;
  const std::size_t block = std::clamp<std::size_t>((8u << 20) / frame_bytes, 1, 1024);
  std::vector<std::vector<unsigned char>> rows(cols.size());
  std::vector<std::uint64_t> sums;

  // reads frames [first, first + count) and returns how many leading frames check out
  auto verify = [&](std::size_t first, std::size_t count) -> std::size_t {
    try {
      for (std::size_t k = 0; k < cols.size(); ++k) {
        rows[k].resize(count * cols[k].row_bytes);
        h5::read_rows(cols[k].dset->get(), cols[k].mem_type, first, count, rows[k].data(), "verify");
      }
      sums.resize(count);
      h5::read_rows(checksum.get(), H5T_NATIVE_UINT64, first, count, sums.data(), "verify");
    } catch (const h5::Failure&) {
      return 0;
    }
    for (std::size_t i = 0; i < count; ++i) {
      std::uint64_t h = kFnvOffset;
      for (std::size_t k = 0; k < cols.size(); ++k) {
        h = fnv1a(h, rows[k].data() + i * cols[k].row_bytes, cols[k].row_bytes);
      }
      if (h != sums[i]) return i;
    }
    return count;
  };
  for (std::size_t first = 0; first < announced; first += block) {
    const std::size_t count = std::min(block, announced - first);
    if (verify(first, count) == count) continue;
    // a read error hides which frame is bad: look one frame at a time
    for (std::size_t i = first; i < first + count; ++i) {
      if (verify(i, 1) != 1) return i;
    }
  }
  return announced;
}

ResultReader::ResultReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ResultReader::~ResultReader() = default;

std::unique_ptr<ResultReader> ResultReader::open(const std::string& path, std::string* error) {
  h5::Quiet quiet;
  const std::string prefix = "cannot open results file '" + path + "': ";
  auto set = [&](const std::string& why) {
    if (error) *error = prefix + why;
    return nullptr;
  };
  std::error_code ec;
  auto st = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(st)) return set("no such file");
  if (std::filesystem::is_directory(st)) return set("it is a directory");
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    // H5Fis_hdf5 also fails on unreadable files: say which
    if (!std::ifstream(path, std::ios::binary)) return set("the file cannot be read (permissions?)");
    if (!has_hdf5_signature(path)) return set("not an HDF5 file (no HDF5 signature)");
  }
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  try {
    h5::Handle fapl(h5::check_id(H5Pcreate(H5P_FILE_ACCESS), "file access properties"));
#if H5_VERSION_GE(1, 10, 7)
    h5::check(H5Pset_file_locking(fapl.get(), 1, 1), "file access properties");
#endif
    impl->file = h5::Handle(h5::check_id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), ""));
    impl->load_all();
  } catch (const h5::Failure& e) {
    return set(e.what());
  } catch (const std::out_of_range& e) {
    return set(std::string("malformed file: ") + e.what());
  }
  return std::unique_ptr<ResultReader>(new ResultReader(std::move(impl)));
}

const RunInfo& ResultReader::info() const { return impl_->info; }
std::size_t ResultReader::frame_count() const { return impl_->frame_count; }
RunOutcome ResultReader::outcome() const { return impl_->outcome; }
std::vector<std::pair<std::string, double>> ResultReader::metrics() const { return impl_->metrics; }
std::vector<std::pair<std::string, std::string>> ResultReader::attributes() const {
  return impl_->attributes;
}
const std::string& ResultReader::path() const { return impl_->path; }

Frame ResultReader::frame(std::size_t i) const {
  const Impl& m = *impl_;
  if (i >= m.frame_count) {
    throw std::out_of_range(m.what("frame " + std::to_string(i) + " requested, the file has " +
                                   std::to_string(m.frame_count)));
  }
  h5::Quiet quiet;
  const std::string what = m.what("read frame " + std::to_string(i));
  const std::size_t n = m.info.mesh.point_count();
  Frame fr;
  std::int8_t converged = 1;
  try {
    h5::read_rows(m.time.get(), H5T_NATIVE_DOUBLE, i, 1, &fr.time, what);
    h5::read_rows(m.step.get(), H5T_NATIVE_INT64, i, 1, &fr.step, what);
    h5::read_rows(m.load.get(), H5T_NATIVE_DOUBLE, i, 1, &fr.load_factor, what);
    h5::read_rows(m.dt.get(), H5T_NATIVE_DOUBLE, i, 1, &fr.stats.dt, what);
    h5::read_rows(m.iterations.get(), H5T_NATIVE_INT32, i, 1, &fr.stats.iterations, what);
    h5::read_rows(m.jacobian_updates.get(), H5T_NATIVE_INT32, i, 1, &fr.stats.jacobian_updates,
                  what);
    h5::read_rows(m.residual.get(), H5T_NATIVE_DOUBLE, i, 1, &fr.stats.residual_norm, what);
    h5::read_rows(m.increment.get(), H5T_NATIVE_DOUBLE, i, 1, &fr.stats.increment_norm, what);
    hid_t conv_type = m.converged_mem_type.valid() ? m.converged_mem_type.get() : H5T_NATIVE_INT8;
    h5::read_rows(m.converged.get(), conv_type, i, 1, &converged, what);
    fr.stats.converged = converged != 0;
    fr.points.resize(3 * n);
    fr.base_points.resize(3 * n);
    h5::read_rows(m.points.get(), H5T_NATIVE_DOUBLE, i, 1, fr.points.data(), what);
    h5::read_rows(m.base_points.get(), H5T_NATIVE_DOUBLE, i, 1, fr.base_points.data(), what);
    fr.probes.resize(m.probes.size());
    for (std::size_t k = 0; k < m.probes.size(); ++k) {
      h5::read_rows(m.probes[k].get(), H5T_NATIVE_DOUBLE, i, 1, &fr.probes[k], what);
    }
    fr.fields.assign(m.fields.size(), std::vector<double>(n));
    for (std::size_t k = 0; k < m.fields.size(); ++k) {
      h5::read_rows(m.fields[k].get(), H5T_NATIVE_DOUBLE, i, 1, fr.fields[k].data(), what);
    }
  } catch (const h5::Failure& e) {
    throw std::runtime_error(e.what());
  }
  return fr;
}

std::vector<double> ResultReader::times() const {
  h5::Quiet quiet;
  try {
    return impl_->column<double>(impl_->time, H5T_NATIVE_DOUBLE, "frames/time");
  } catch (const h5::Failure& e) {
    throw std::runtime_error(e.what());
  }
}

std::vector<double> ResultReader::probe_series(const std::string& name) const {
  const Impl& m = *impl_;
  for (std::size_t k = 0; k < m.info.probes.size(); ++k) {
    if (m.info.probes[k].name != name) continue;
    h5::Quiet quiet;
    try {
      return m.column<double>(m.probes[k], H5T_NATIVE_DOUBLE, ("frames/probes/" + name).c_str());
    } catch (const h5::Failure& e) {
      throw std::runtime_error(e.what());
    }
  }
  return {};
}

std::vector<StepStats> ResultReader::stats() const {
  const Impl& m = *impl_;
  h5::Quiet quiet;
  std::vector<StepStats> out(m.frame_count);
  try {
    auto dt = m.column<double>(m.dt, H5T_NATIVE_DOUBLE, "frames/stats/dt");
    auto it = m.column<std::int32_t>(m.iterations, H5T_NATIVE_INT32, "frames/stats/iterations");
    auto ju = m.column<std::int32_t>(m.jacobian_updates, H5T_NATIVE_INT32,
                                     "frames/stats/jacobian_updates");
    auto rn = m.column<double>(m.residual, H5T_NATIVE_DOUBLE, "frames/stats/residual_norm");
    auto in = m.column<double>(m.increment, H5T_NATIVE_DOUBLE, "frames/stats/increment_norm");
    hid_t conv_type = m.converged_mem_type.valid() ? m.converged_mem_type.get() : H5T_NATIVE_INT8;
    auto cv = m.column<std::int8_t>(m.converged, conv_type, "frames/stats/converged");
    for (std::size_t i = 0; i < m.frame_count; ++i) {
      out[i] = StepStats{dt[i], it[i], ju[i], rn[i], in[i], cv[i] != 0};
    }
  } catch (const h5::Failure& e) {
    throw std::runtime_error(e.what());
  }
  return out;
}

std::vector<StepRecord> ResultReader::step_log() const {
  const Impl& m = *impl_;
  h5::Quiet quiet;
  std::vector<StepRecord> out;
  try {
    hid_t f = m.file.get();
    if (!h5::has_link(f, names::kSteps)) {  // an older file: the frames are the steps
      const std::vector<StepStats> st = stats();
      for (std::size_t i = 0; i < st.size(); ++i) {
        const Frame fr = frame(i);
        if (fr.step > 0) out.push_back({fr.step, fr.time, st[i]});
      }
      return out;
    }
    h5::Handle g = h5::open_group(f, names::kSteps);
    const auto n = static_cast<std::size_t>(h5::read_attr_int64(g.get(), names::kStepsWritten));
    const auto read = [&](const char* name, hid_t type, void* dst) {
      h5::Handle d = h5::open_dataset(g.get(), name);
      h5::read_rows(d.get(), type, 0, n, dst, m.what(std::string("read steps/") + name));
    };
    std::vector<std::int64_t> step(n);
    std::vector<double> time(n), dt(n), res(n), inc(n);
    std::vector<std::int32_t> it(n), ju(n);
    std::vector<std::int8_t> cv(n);
    read("step", H5T_NATIVE_INT64, step.data());
    read("time", H5T_NATIVE_DOUBLE, time.data());
    read("dt", H5T_NATIVE_DOUBLE, dt.data());
    read("iterations", H5T_NATIVE_INT32, it.data());
    read("jacobian_updates", H5T_NATIVE_INT32, ju.data());
    read("residual_norm", H5T_NATIVE_DOUBLE, res.data());
    read("increment_norm", H5T_NATIVE_DOUBLE, inc.data());
    read("converged", m.converged_mem_type.valid() ? m.converged_mem_type.get() : H5T_NATIVE_INT8, cv.data());
    for (std::size_t i = 0; i < n; ++i) out.push_back({step[i], time[i], StepStats{dt[i], it[i], ju[i], res[i], inc[i], cv[i] != 0}});
  } catch (const h5::Failure& e) {
    throw std::runtime_error(e.what());
  }
  return out;
}

}  // namespace ff::io
