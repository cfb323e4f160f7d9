/// \file result_reader.cpp
/// ResultReader: opens results.h5 (finished, interrupted or killed), reads the constant parts
/// at open and frame data on demand. Trusts frames_written, never the raw data set extents.

#include <algorithm>
#include <bit>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/io/frame_checksum.h"
#include "app/io/h5_util.h"
#include "app/io/results.h"
#include "app/io/results_names.h"
#include "core/frame/input_file.h"

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

// Rows [first, first + count) of a data set chunked by rows, as stored, read chunk by chunk
// past the filter (H5Dread_chunk): Fletcher32 keeps the rows unchanged and appends 4 checksum
// bytes. Not H5Dread with the check disabled (H5Z_DISABLE_EDC), which would leave the
// unchecked chunk in the chunk cache for every later read to return.
void read_raw_rows(hid_t dset, std::size_t row_bytes, hsize_t first, hsize_t count, unsigned char* out) {
  const std::string what = "read stored chunks";
  h5::Handle dcpl(h5::check_id(H5Dget_create_plist(dset), what));
  const std::vector<hsize_t> dims = h5::dataset_dims(dset);
  std::vector<hsize_t> chunk(dims.size());
  unsigned flags = 0;
  std::size_t n = 0;
  if (H5Pget_layout(dcpl.get()) != H5D_CHUNKED || dims.empty() ||
      H5Pget_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) != static_cast<int>(dims.size()) ||
      H5Pget_nfilters(dcpl.get()) != 1 ||
      H5Pget_filter_by_id2(dcpl.get(), H5Z_FILTER_FLETCHER32, &flags, &n, nullptr, 0, nullptr, nullptr) < 0) {
    throw h5::Failure(what + ": not chunked by frames with the Fletcher32 filter alone");
  }
  for (std::size_t k = 1; k < dims.size(); ++k) {
    if (chunk[k] != dims[k]) throw h5::Failure(what + ": a chunk holds part of a row");
  }
  const hsize_t per = chunk[0];
  std::vector<unsigned char> buf;
  for (hsize_t c = first / per; c * per < first + count; ++c) {
    std::vector<hsize_t> origin(dims.size(), 0);
    origin[0] = c * per;
    hsize_t bytes = 0;
    h5::check(H5Dget_chunk_storage_size(dset, origin.data(), &bytes), what);
    if (bytes < per * row_bytes) throw h5::Failure(what + ": a stored chunk is short");
    buf.resize(static_cast<std::size_t>(bytes));
    std::uint32_t mask = 0;
    h5::check(H5Dread_chunk(dset, H5P_DEFAULT, origin.data(), &mask, buf.data()), what);
    const hsize_t lo = std::max(first, origin[0]), hi = std::min(first + count, origin[0] + per);
    std::copy_n(buf.data() + (lo - origin[0]) * row_bytes, (hi - lo) * row_bytes, out + (lo - first) * row_bytes);
  }
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
  std::optional<ModeSet> modes;

  h5::Handle time, step, load, dt, iterations, jacobian_updates, residual, increment, converged;
  h5::Handle converged_mem_type;  // the file's enum as a native type, or invalid (plain int)
  h5::Handle points, base_points;
  std::vector<h5::Handle> probes, fields;
  h5::Handle checksum;  // invalid in files without one
  std::size_t damaged_frames = 0;  // announced by frames_written but failing their checksum

  bool frames_verified = false;  // by count_verified_frames at open

  /// A frame data set in checksum order, with the memory type and bytes of one row.
  struct ColumnRef {
    const h5::Handle* dset;
    hid_t mem_type;
    std::size_t row_bytes;
    std::string name;  // path in the file, for messages
  };
  std::vector<ColumnRef> checksum_order() const;
  // the frame columns in checksum order and how many frames to read at once (about 8 MB)
  struct FrameBlocks {
    std::vector<ColumnRef> cols;
    std::size_t block = 1;
  };
  FrameBlocks frame_blocks() const;
  std::size_t count_verified_frames(std::size_t announced) const;
  std::string find_damage() const;
  std::string frame_damage(const std::vector<ColumnRef>& cols, std::size_t k, std::size_t first,
                           std::size_t count, const std::string& reason) const;
  std::string steps_damage() const;
  std::string frame_label(std::size_t i) const;
  void load_all();
  void load_modes();
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
  if (const std::string why = file_names_problem(info); !why.empty())
    throw h5::Failure(why + " (flexframe never writes such a file)");

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
    if (h5::has_attr(o.get(), "cutbacks")) outcome.cutbacks = h5::read_attr_int64(o.get(), "cutbacks");
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
      frames_verified = true;
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
  // the modes of an eigen-analysis: written whole and flushed before the outcome, so a file
  // that has the group has all of it, unless a kill hit that one flush
  try {
    load_modes();
  } catch (const h5::Failure&) {
    if (finished) throw;
    modes.reset();
  }
}

void ResultReader::Impl::load_modes() {
  hid_t f = file.get();
  if (!h5::has_link(f, names::kModes)) return;
  h5::Handle g = h5::open_group(f, names::kModes);
  ModeSet set;
  set.analysis = h5::read_attr_string(g.get(), "analysis");
  set.about = h5::read_attr_string(g.get(), "about");
  set.value_name = h5::read_attr_string(g.get(), "value_name");
  set.value_unit = h5::read_attr_string(g.get(), "value_unit");
  set.value_label = h5::read_attr_string(g.get(), "value_label");
  const std::int64_t count = h5::read_attr_int64(g.get(), "count");
  const std::size_t n = info.mesh.point_count();
  const auto read_all = [&](const char* name, hid_t mem_type, std::size_t per_mode, void* out) {
    h5::Handle d = h5::open_dataset(g.get(), name);
    const std::vector<hsize_t> dims = h5::dataset_dims(d.get());
    hsize_t elements = 1;
    for (hsize_t e : dims) elements *= e;
    if (dims.empty() || dims[0] != static_cast<hsize_t>(count) || elements != static_cast<hsize_t>(count) * per_mode)
      throw h5::Failure(std::string(names::kModes) + "/" + name + " does not hold " + std::to_string(count) + " x " +
                        std::to_string(per_mode) + " values");
    if (elements > 0)
      h5::check(H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out),
                "read data set '" + std::string(names::kModes) + "/" + name + "'");
  };
  const std::size_t m = static_cast<std::size_t>(std::max<std::int64_t>(count, 0));
  std::vector<std::int64_t> numbers(m);
  std::vector<double> values(m), eigenvalues(m), displacement(3 * n * m);
  std::vector<std::int8_t> rigid(m);
  read_all("number", H5T_NATIVE_INT64, 1, numbers.data());
  read_all("value", H5T_NATIVE_DOUBLE, 1, values.data());
  read_all("eigenvalue", H5T_NATIVE_DOUBLE, 1, eigenvalues.data());
  {
    h5::Handle d = h5::open_dataset(g.get(), "rigid_body");
    h5::Handle t(h5::check_id(H5Dget_type(d.get()), "type of modes/rigid_body"));
    h5::Handle native(h5::check_id(H5Tget_native_type(t.get(), H5T_DIR_DEFAULT), "modes/rigid_body"));
    if (H5Tget_size(native.get()) != 1) throw h5::Failure("modes/rigid_body is not a one-byte flag");
    read_all("rigid_body", native.get(), 1, rigid.data());
  }
  read_all("displacement", H5T_NATIVE_DOUBLE, 3 * n, displacement.data());
  for (std::size_t k = 0; k < m; ++k) {
    Mode mode;
    mode.number = static_cast<std::int32_t>(numbers[k]);
    mode.value = values[k];
    mode.eigenvalue = eigenvalues[k];
    mode.rigid_body = rigid[k] != 0;
    mode.displacement.assign(displacement.begin() + static_cast<std::ptrdiff_t>(3 * n * k),
                             displacement.begin() + static_cast<std::ptrdiff_t>(3 * n * (k + 1)));
    set.modes.push_back(std::move(mode));
  }
  modes = std::move(set);
}

std::vector<ResultReader::Impl::ColumnRef> ResultReader::Impl::checksum_order() const {
  const std::size_t n = info.mesh.point_count();
  hid_t conv = converged_mem_type.valid() ? converged_mem_type.get() : H5T_NATIVE_INT8;
  const std::string fr = names::kFrames, st = names::kStats;
  std::vector<ColumnRef> cols{{&time, H5T_NATIVE_DOUBLE, 8, fr + "/time"},
                              {&step, H5T_NATIVE_INT64, 8, fr + "/step"},
                              {&load, H5T_NATIVE_DOUBLE, 8, fr + "/load_factor"},
                              {&dt, H5T_NATIVE_DOUBLE, 8, st + "/dt"},
                              {&iterations, H5T_NATIVE_INT32, 4, st + "/iterations"},
                              {&jacobian_updates, H5T_NATIVE_INT32, 4, st + "/jacobian_updates"},
                              {&residual, H5T_NATIVE_DOUBLE, 8, st + "/residual_norm"},
                              {&increment, H5T_NATIVE_DOUBLE, 8, st + "/increment_norm"},
                              {&converged, conv, 1, st + "/converged"},
                              {&points, H5T_NATIVE_DOUBLE, 24 * n, fr + "/points"},
                              {&base_points, H5T_NATIVE_DOUBLE, 24 * n, fr + "/base_points"}};
  for (std::size_t k = 0; k < probes.size(); ++k)
    cols.push_back({&probes[k], H5T_NATIVE_DOUBLE, 8, std::string(names::kProbes) + "/" + info.probes[k].name});
  for (std::size_t k = 0; k < fields.size(); ++k)
    cols.push_back({&fields[k], H5T_NATIVE_DOUBLE, 8 * n, std::string(names::kFields) + "/" + info.fields[k].name});
  return cols;
}

// the first frame (from 0) that cannot be read or fails its checksum ends the run
ResultReader::Impl::FrameBlocks ResultReader::Impl::frame_blocks() const {
  FrameBlocks b;
  b.cols = checksum_order();
  std::size_t frame_bytes = 8;
  for (const auto& c : b.cols) frame_bytes += c.row_bytes;
  b.block = std::clamp<std::size_t>((8u << 20) / frame_bytes, 1, 1024);
  return b;
}

std::size_t ResultReader::Impl::count_verified_frames(std::size_t announced) const {
  const auto [cols, block] = frame_blocks();
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

// "frame 5 of 11 (t = 0.25 s)"; the time is left out when it cannot be read either
std::string ResultReader::Impl::frame_label(std::size_t i) const {
  std::ostringstream s;
  s << "frame " << i << " of " << frame_count;
  double t = 0;
  try {
    h5::read_rows(time.get(), H5T_NATIVE_DOUBLE, i, 1, &t, "time");
    s << " (t = " << t << (info.time_unit.empty() ? "" : " ") << info.time_unit << ")";
  } catch (const h5::Failure&) {
  }
  return s.str();
}

// Every frame row once, in blocks of frames: damage is a chunk that fails its Fletcher32
// checksum (HDF5 then refuses to read it) or a frame whose rows do not hash to /frames/checksum
// (the only check in files written before the filter was used).
std::string ResultReader::Impl::find_damage() const {
  if (frames_verified) return steps_damage();
  const auto [cols, block] = frame_blocks();
  std::vector<std::vector<unsigned char>> rows(cols.size());
  std::vector<std::uint64_t> sums;
  for (std::size_t first = 0; first < frame_count; first += block) {
    const std::size_t count = std::min(block, frame_count - first);
    for (std::size_t k = 0; k < cols.size(); ++k) {
      rows[k].resize(count * cols[k].row_bytes);
      try {
        h5::read_rows(cols[k].dset->get(), cols[k].mem_type, first, count, rows[k].data(), "read");
      } catch (const h5::Failure& e) {
        return frame_damage(cols, k, first, count, e.reason_or_what());
      }
    }
    if (!checksum.valid()) continue;
    sums.resize(count);
    try {
      h5::read_rows(checksum.get(), H5T_NATIVE_UINT64, first, count, sums.data(), "read");
    } catch (const h5::Failure& e) {
      return frame_damage(cols, cols.size(), first, count, e.reason_or_what());
    }
    for (std::size_t i = 0; i < count; ++i) {
      std::uint64_t h = kFnvOffset;
      for (std::size_t k = 0; k < cols.size(); ++k) {
        h = fnv1a(h, rows[k].data() + i * cols[k].row_bytes, cols[k].row_bytes);
      }
      if (h != sums[i]) {
        return what(frame_label(first + i) + " is damaged: its rows do not match " +
                    std::string(names::kFrames) + "/checksum");
      }
    }
  }
  return steps_damage();
}

// Column k (cols.size(): /frames/checksum) could not be read in frames [first, first + count):
// narrows it down to the rows that fail (Fletcher32 fails a whole chunk), then reads them past
// the check to find the frame whose bytes changed, and says which data set and frame it is.
std::string ResultReader::Impl::frame_damage(const std::vector<ColumnRef>& cols, std::size_t k,
                                             std::size_t first, std::size_t count,
                                             const std::string& reason) const {
  const bool is_sum = k == cols.size();
  const h5::Handle& d = is_sum ? checksum : *cols[k].dset;
  const hid_t type = is_sum ? H5T_NATIVE_UINT64 : cols[k].mem_type;
  const std::string name = is_sum ? std::string(names::kFrames) + "/checksum" : cols[k].name;
  std::vector<unsigned char> row(is_sum ? 8 : std::max<std::size_t>(cols[k].row_bytes, 1));
  const auto readable = [&](std::size_t i) {
    try {
      h5::read_rows(d.get(), type, i, 1, row.data(), "read");
      return true;
    } catch (const h5::Failure&) {
      return false;
    }
  };
  std::size_t bad = first;
  while (bad + 1 < first + count && readable(bad)) ++bad;
  std::size_t bad_end = bad + 1;
  while (bad_end < first + count && !readable(bad_end)) ++bad_end;
  std::size_t frame = bad;
  // the rows as stored: the frame whose rows no longer hash to /frames/checksum is the damaged one
  if (checksum.valid()) {
    try {
      const std::size_t n = bad_end - bad;
      std::vector<std::uint64_t> sums(n);
      if (is_sum) {
        read_raw_rows(checksum.get(), 8, bad, n, reinterpret_cast<unsigned char*>(sums.data()));
      } else {
        h5::read_rows(checksum.get(), H5T_NATIVE_UINT64, bad, n, sums.data(), "read");
      }
      std::vector<std::uint64_t> h(n, kFnvOffset);
      for (std::size_t j = 0; j < cols.size(); ++j) {
        std::vector<unsigned char> data(n * cols[j].row_bytes);
        if (j == k) {
          read_raw_rows(cols[j].dset->get(), cols[j].row_bytes, bad, n, data.data());
        } else {
          h5::read_rows(cols[j].dset->get(), cols[j].mem_type, bad, n, data.data(), "read");
        }
        for (std::size_t i = 0; i < n; ++i) h[i] = fnv1a(h[i], data.data() + i * cols[j].row_bytes, cols[j].row_bytes);
      }
      for (std::size_t i = 0; i < n; ++i) {
        if (h[i] != sums[i]) {
          frame = bad + i;
          break;
        }
      }
    } catch (const h5::Failure&) {  // more is damaged: the first unreadable row it is
    }
  }
  std::string s = "data set '" + name + "' is damaged at " + frame_label(frame) + ": " + reason;
  if (bad_end - bad > 1) {
    s += " (frames " + std::to_string(bad) + ".." + std::to_string(bad_end - 1) +
         " share the damaged chunk)";
  }
  return what(s);
}

// the per-step convergence log: every data set under /steps, steps_written rows
std::string ResultReader::Impl::steps_damage() const {
  hid_t f = file.get();
  if (!h5::has_link(f, names::kSteps)) return {};
  h5::Handle g = h5::open_group(f, names::kSteps);
  const auto n = static_cast<std::size_t>(
      std::max<std::int64_t>(0, h5::read_attr_int64(g.get(), names::kStepsWritten)));
  for (const char* name : {"step", "time", "dt", "iterations", "jacobian_updates", "residual_norm",
                           "increment_norm", "converged"}) {
    if (!h5::has_link(g.get(), name)) continue;
    const std::string path = std::string(names::kSteps) + "/" + name;
    h5::Handle d = h5::open_dataset(g.get(), name);
    h5::Handle type(h5::check_id(H5Dget_type(d.get()), "type of " + path));
    const std::size_t bytes = H5Tget_size(type.get());
    const std::size_t rows = std::min<std::size_t>(n, h5::dataset_dims(d.get()).at(0));
    const std::size_t block = 65536;
    std::vector<unsigned char> buf(block * bytes);
    for (std::size_t first = 0; first < rows; first += block) {
      const std::size_t count = std::min(block, rows - first);
      std::string reason;
      try {
        h5::read_rows(d.get(), type.get(), first, count, buf.data(), "read");
        continue;
      } catch (const h5::Failure& e) {
        reason = e.reason_or_what();
      }
      std::size_t bad = first;
      for (; bad + 1 < first + count; ++bad) {
        try {
          h5::read_rows(d.get(), type.get(), bad, 1, buf.data(), "read");
        } catch (const h5::Failure&) {
          break;
        }
      }
      return what("data set '" + path + "' is damaged at row " + std::to_string(bad) + " of " +
                  std::to_string(n) + " (solver steps): " + reason);
    }
  }
  return {};
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
  // a regular file (HDF5 reads it in parts, as it needs them: no size bound)
  if (const std::string problem = input_file_problem(path, 0, ""); !problem.empty()) return set("it " + problem);
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
const ModeSet* ResultReader::modes() const { return impl_->modes ? &*impl_->modes : nullptr; }
const std::string& ResultReader::path() const { return impl_->path; }

Frame ResultReader::frame(std::size_t i) const {
  const Impl& m = *impl_;
  if (i >= m.frame_count) {
    throw std::out_of_range(m.what("frame " + std::to_string(i) + " requested, the file has " +
                                   std::to_string(m.frame_count)));
  }
  h5::Quiet quiet;
  const std::size_t n = m.info.mesh.point_count();
  Frame fr;
  std::int8_t converged = 1;
  // a failed read names the data set and the frame: "results file 'x': frame 5: data set ..."
  const auto read = [&](const h5::Handle& d, hid_t type, void* out, const std::string& name) {
    h5::read_rows(d.get(), type, i, 1, out, m.what("frame " + std::to_string(i) + ": data set '" + name + "'"));
  };
  const std::string f = names::kFrames, st = names::kStats;
  try {
    read(m.time, H5T_NATIVE_DOUBLE, &fr.time, f + "/time");
    read(m.step, H5T_NATIVE_INT64, &fr.step, f + "/step");
    read(m.load, H5T_NATIVE_DOUBLE, &fr.load_factor, f + "/load_factor");
    read(m.dt, H5T_NATIVE_DOUBLE, &fr.stats.dt, st + "/dt");
    read(m.iterations, H5T_NATIVE_INT32, &fr.stats.iterations, st + "/iterations");
    read(m.jacobian_updates, H5T_NATIVE_INT32, &fr.stats.jacobian_updates, st + "/jacobian_updates");
    read(m.residual, H5T_NATIVE_DOUBLE, &fr.stats.residual_norm, st + "/residual_norm");
    read(m.increment, H5T_NATIVE_DOUBLE, &fr.stats.increment_norm, st + "/increment_norm");
    hid_t conv_type = m.converged_mem_type.valid() ? m.converged_mem_type.get() : H5T_NATIVE_INT8;
    read(m.converged, conv_type, &converged, st + "/converged");
    fr.stats.converged = converged != 0;
    fr.points.resize(3 * n);
    fr.base_points.resize(3 * n);
    read(m.points, H5T_NATIVE_DOUBLE, fr.points.data(), f + "/points");
    read(m.base_points, H5T_NATIVE_DOUBLE, fr.base_points.data(), f + "/base_points");
    fr.probes.resize(m.probes.size());
    for (std::size_t k = 0; k < m.probes.size(); ++k) {
      read(m.probes[k], H5T_NATIVE_DOUBLE, &fr.probes[k], std::string(names::kProbes) + "/" + m.info.probes[k].name);
    }
    fr.fields.assign(m.fields.size(), std::vector<double>(n));
    for (std::size_t k = 0; k < m.fields.size(); ++k) {
      read(m.fields[k], H5T_NATIVE_DOUBLE, fr.fields[k].data(), std::string(names::kFields) + "/" + m.info.fields[k].name);
    }
  } catch (const h5::Failure& e) {
    throw std::runtime_error(e.what());
  }
  return fr;
}

std::string ResultReader::verify() const {
  h5::Quiet quiet;
  try {
    return impl_->find_damage();
  } catch (const h5::Failure& e) {
    return impl_->what(e.what());
  }
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
