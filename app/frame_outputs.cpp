#include "app/frame_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/io/frame_export.h"
#include "app/io/movie_writer.h"
#include "core/frame/file_name.h"
#include "render/frame_layout.h"
#include "render/image_io.h"
#include "render/mesh_export.h"

namespace fs = std::filesystem;

namespace ff::app {

std::vector<std::size_t> frame_selection(std::size_t count, int every, bool include_last) {
  std::vector<std::size_t> out;
  const std::size_t step = static_cast<std::size_t>(std::max(every, 1));
  for (std::size_t i = 0; i < count; i += step) out.push_back(i);
  if (include_last && count > 0 && out.back() != count - 1) out.push_back(count - 1);
  return out;
}

std::array<double, 2> field_range(const io::ResultReader& reader, const std::vector<std::size_t>& frames,
                                  int field) {
  double lo = 0, hi = 0;
  bool any = false;
  if (field < 0) return {0, 0};
  for (std::size_t i : frames) {
    const Frame f = reader.frame(i);
    for (double v : f.fields.at(static_cast<std::size_t>(field))) {
      if (!std::isfinite(v)) continue;
      lo = any ? std::min(lo, v) : v;
      hi = any ? std::max(hi, v) : v;
      any = true;
    }
  }
  return {lo, hi};
}

SequenceView sequence_view(std::size_t count, const std::function<Frame(std::size_t)>& frame_at, int field,
                           double deformation_scale, const std::atomic<bool>& stop) {
  SequenceView view;
  double lo = 0, hi = 0;
  bool any = false;
  const std::size_t fit_stride = std::max<std::size_t>(1, count / kMaxFitFrames);
  for (std::size_t k = 0; k < count && !stop; ++k) {
    const Frame f = frame_at(k);
    if (field >= 0 && static_cast<std::size_t>(field) < f.fields.size()) {
      for (double v : f.fields[static_cast<std::size_t>(field)]) {
        if (!std::isfinite(v)) continue;
        lo = any ? std::min(lo, v) : v;
        hi = any ? std::max(hi, v) : v;
        any = true;
      }
    }
    if (k % fit_stride != 0 && k + 1 != count) continue;
    const bool have_base = f.base_points.size() == f.points.size();
    std::vector<double> drawn(f.points.size());
    bool finite = true;
    for (std::size_t i = 0; i < f.points.size(); ++i) {
      const double b = have_base ? f.base_points[i] : f.points[i];
      drawn[i] = b + deformation_scale * (f.points[i] - b);
      finite = finite && std::isfinite(drawn[i]);
    }
    if (finite) view.fit_points.insert(view.fit_points.end(), drawn.begin(), drawn.end());
  }
  if (any) view.color_range = render::color_range_for(lo, hi);
  return view;
}

int field_index(const RunInfo& info, const std::string& name) {
  for (std::size_t k = 0; k < info.fields.size(); ++k)
    if (info.fields[k].name == name) return static_cast<int>(k);
  return -1;
}

std::string field_names(const RunInfo& info) {
  std::string s;
  for (const Quantity& q : info.fields) s += (s.empty() ? "" : ", ") + q.name;
  return s.empty() ? "(none)" : s;
}

MovieReport write_movie(const std::string& frames_dir, const std::string& movie_path, int fps,
                        const std::atomic<bool>& stop) {
  MovieReport r;
  if (const std::string why = io::movie_support(); !why.empty()) {
    r.message = why + "; the PNG frames are kept";
    return r;
  }
  std::vector<std::string> pngs;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(frames_dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".png" && name.rfind("frame_", 0) == 0) pngs.push_back(e.path().string());
  }
  std::sort(pngs.begin(), pngs.end());
  if (pngs.empty()) {
    r.message = "no frames in " + frames_dir + " to make a movie of";
    return r;
  }
  render::RgbImage first;
  if (!render::read_png_rgb(pngs.front(), &first, &r.message)) return r;
  std::unique_ptr<io::MovieWriter> movie = io::MovieWriter::create(movie_path, first.width, first.height, fps, &r.message);
  if (!movie) return r;
  r.codec = movie->codec();
  render::RgbImage img;
  for (const std::string& png : pngs) {
    if (stop) {
      r.message = "stopped after " + std::to_string(movie->frames_added()) + " movie frames";
      break;
    }
    if (!render::read_png_rgb(png, &img, &r.message)) break;
    if (img.width != first.width || img.height != first.height) {
      r.message = png + " is " + std::to_string(img.width) + "x" + std::to_string(img.height) + ", the movie is " +
                  std::to_string(first.width) + "x" + std::to_string(first.height);
      break;
    }
    if (!movie->add_frame(img.rgb.data(), &r.message)) break;
  }
  std::string finish_error;
  const bool finished = movie->finish(&finish_error);
  r.frames = movie->frames_added();
  if (r.message.empty() && !finished) r.message = finish_error;
  r.ok = r.message.empty();
  if (r.ok) r.path = movie_path;
  return r;
}

ExportReport export_frames(const io::ResultReader& reader, const std::vector<std::size_t>& frames,
                           const ExportFormats& formats, const std::string& dir, int color_field,
                           std::array<double, 2> range, const std::atomic<bool>& stop) {
  ExportReport r;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) {
    r.error = "cannot create the export folder " + dir;
    return r;
  }
  const RunInfo& info = reader.info();
  std::vector<render::PvdEntry> pvd;
  for (std::size_t k = 0; k < frames.size() && r.error.empty() && !stop; ++k) {
    Frame f;
    try {
      f = reader.frame(frames[k]);
    } catch (const std::exception& e) {
      r.error = e.what();
      break;
    }
    char stem[32];
    std::snprintf(stem, sizeof stem, "frame_%05zu", k);
    const fs::path base = fs::path(dir) / stem;
    if (formats.vtu) {
      const std::string file = std::string(stem) + ".vtu";
      if (!render::write_vtu((fs::path(dir) / file).string(), info, f, &r.error)) break;
      pvd.push_back({f.time, file});
      r.written.push_back(file);
      if (k == 0) r.files.push_back((fs::path(dir) / file).string());
    }
    for (auto [wanted, format] : {std::pair{formats.gltf, io::MeshFileFormat::gltf_binary},
                                  std::pair{formats.obj, io::MeshFileFormat::obj}}) {
      if (!wanted) continue;
      const std::string path = base.string() + "." + io::extension(format);
      std::vector<std::string> files;  // an OBJ writes its .mtl beside it
      const bool ok = io::write_frame_mesh(path, format, info, f, color_field, range, &r.error, &files);
      for (const std::string& file : files) r.written.push_back(fs::path(file).filename().string());
      if (!ok) break;
      if (k == 0) r.files.push_back(path);
    }
    if (r.error.empty()) ++r.frames;
  }
  if (formats.vtu && !pvd.empty()) {
    const std::string name = (info.scene_name.empty() ? std::string("frames") : info.scene_name) + ".pvd";
    std::string e;
    // a name becomes a file name only once it is known to be one (the last word: results files
    // are checked on reading, scenes at their key)
    if (const std::string why = file_name_problem(info.scene_name); !info.scene_name.empty() && !why.empty())
      e = "the scene name '" + info.scene_name + "' " + why + ": no .pvd file made";
    else if (render::write_pvd((fs::path(dir) / name).string(), pvd, &e)) {
      r.files.insert(r.files.begin(), (fs::path(dir) / name).string());
      r.written.push_back(name);
    }
    if (!e.empty() && r.error.empty()) r.error = e;
  }
  return r;
}

}  // namespace ff::app
