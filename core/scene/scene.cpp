#include "core/scene/scene.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <variant>
#include <toml++/toml.h>

#include "core/frame/file_name.h"
#include "core/frame/input_file.h"
#include "core/scene/hub_beam_scene.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/scene_common.h"
#include "core/scene/schema_text.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_eigen_scene.h"
#include "core/scene/shell_scene.h"
#include "core/scene/structure_parts.h"
#include "core/scene/timeline.h"
#include "core/shell/shell_model.h"

namespace ff::scene {

const std::vector<ModelKind>& model_kinds() {
  // one line per model: its name in scene.model, its schema, the key that ends its run, how a
  // validated document becomes its Simulation, and its memory estimate
  static const std::vector<ModelKind> kinds = [] {
    std::vector<ModelKind> k = {
        {"hub_beam", "", "rotating hub with a flexible beam (EFG or FEM)", hub_beam_schema, "solver.end", false,
         build_hub_beam, estimated_hub_beam_bytes},
        {"shell", "static", "a CB shell structure in equilibrium: linear, load control or arc length",
         shell_static_schema, "solver.end", true, build_shell_static, estimated_structure_bytes},
        {"shell", "dynamic", "a CB shell structure, rigid bodies and joints in motion", shell_dynamic_schema,
         "solver.end", true, build_shell_dynamic, estimated_structure_bytes},
        {"shell", "modal", "natural frequencies and mode shapes of a CB shell structure, unloaded or preloaded",
         shell_modal_schema, "solver.end", true, build_shell_modal, estimated_eigen_bytes},
        {"shell", "buckling", "linear buckling loads and modes of a CB shell structure under its loads",
         shell_buckling_schema, "solver.end", true, build_shell_buckling, estimated_eigen_bytes},
    };
    // every schema's scene.model offers model_names() (scene_common.cpp, below this file)
    std::vector<std::string> names;
    for (const ModelKind& m : k)
      if (names.empty() || names.back() != m.name) names.push_back(m.name);
    if (names != model_names())
      throw std::logic_error("the model registry (scene.cpp) and model_names() (scene_common.cpp) name different models");
    return k;
  }();
  return kinds;
}

const ModelKind* find_model(const std::string& name, const std::string& analysis) {
  for (const ModelKind& k : model_kinds())
    if (k.name == name && k.analysis == analysis) return &k;
  return nullptr;
}

namespace {
// the model named in the file picks the schema; anything unreadable falls back to the first
// model's schema, whose validation then reports the problem with its location
struct Peeked {
  std::string model;     // "" when the file has none (or cannot be parsed)
  std::string analysis;  // scene.analysis, "" when none
  bool given = false;
};
Peeked peek_model_text(const std::string& text, const std::string& path) {
  try {
    const toml::table t = toml::parse(text, path);
    if (const auto m = t["scene"]["model"].value<std::string>())
      return {*m, t["scene"]["analysis"].value<std::string>().value_or(""), true};
  } catch (const toml::parse_error&) {
  }
  return {};
}
// a model's kind: its analysis's, or (no or an unknown analysis) its first, whose validation then
// says what scene.analysis must be
const ModelKind* model_kind(const Peeked& p) {
  if (const ModelKind* k = find_model(p.model, p.analysis)) return k;
  for (const ModelKind& k : model_kinds())
    if (k.name == p.model) return &k;
  return nullptr;
}
const ModelKind& kind_or_first(const Peeked& p) {
  const ModelKind* k = model_kind(p);
  return k ? *k : model_kinds().front();
}
// a model name that is no model: refused at its own line, with the models there are (the shell
// models of before one structure had its analyses say how they are written now)
void refuse_unknown_model(const Peeked& p, const std::string& path, const std::string& text) {
  if (!p.given || model_kind(p)) return;
  std::string known;
  for (const std::string& name : model_names()) known += (known.empty() ? "" : ", ") + name;
  Issue i;
  i.file = path;
  // the line of `model = ...` (the scene table's only key of that name)
  int line = 1;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const std::size_t start = text.find_first_not_of(" \t", k);
    if (start != std::string::npos && text.compare(start, 5, "model") == 0 &&
        text.find_first_not_of(" \t", start + 5) != std::string::npos && text[text.find_first_not_of(" \t", start + 5)] == '=') {
      i.line = line;
      break;
    }
    k = text.find('\n', k);
    if (k == std::string::npos) break;
    ++line;
  }
  i.key = "scene.model";
  i.message = p.model == "shell_static" || p.model == "shell_dynamic"
                  ? "'" + p.model + "' was renamed to model = \"shell\" with analysis = \"" + p.model.substr(6) +
                        "\" (one structure, several analyses)"
                  : "unknown model '" + p.model + "' (models: " + known + ")";
  throw SceneError({i});
}
}  // namespace

const Schema& schema_for_text(const std::string& text) { return kind_or_first(peek_model_text(text, "scene_text")).schema(); }

const Schema& scene_schema(const std::string& path) { return kind_or_first(peek_model_text(read_text_or_empty(path), path)).schema(); }

std::vector<CameraKey> camera_path_from_text(const std::string& text, const std::string& file_name) {
  const Document d = validate(schema_for_text(text), text, file_name);
  return read_timeline(d, 1e300).camera;
}

std::vector<std::string> part_files_in_text(const std::string& text, const std::string& file_name) {
  std::vector<std::string> files;
  try {
    const toml::table doc = toml::parse(text, file_name);
    std::function<void(const toml::node&)> visit = [&](const toml::node& n) {
      if (const toml::table* t = n.as_table()) {
        if (const toml::array* parts = t->get_as<toml::array>("part"))
          for (const toml::node& part : *parts)
            if (const toml::table* p = part.as_table())
              if (const auto* file = p->get_as<std::string>("file")) files.push_back(file->get());
        for (const auto& [key, child] : *t) visit(child);
      } else if (const toml::array* a = n.as_array()) {
        for (const toml::node& child : *a) visit(child);
      }
    };
    visit(doc);
  } catch (const toml::parse_error&) {  // not TOML: no files
  }
  return files;
}

std::string scene_reference_markdown() {
  std::string out;
  for (const ModelKind& k : model_kinds()) {  // appended piece by piece: GCC 12 warns (-Wrestrict) on the sum
    if (!out.empty()) out += "\n";
    out += "## model = \"";
    out += k.name;
    out += "\"";
    if (!k.analysis.empty()) {
      out += ", analysis = \"";
      out += k.analysis;
      out += "\"";
    }
    out += "\n\n";
    out += k.schema().markdown_reference();
  }
  return out;
}

namespace {
// results.h5 keeps one series per probe name and summary.json one value per metric name, so a
// repeated name would fail only when the results file is created (or silently overwrite a
// metric): refuse it here, where check sees it too, at the second entry's own line
void refuse_repeated_names(const Document& d) {
  for (const char* table : {"probe", "arc", "metric"}) {
    if (!d.declares_array(table)) continue;
    const std::string key = std::string(table) + ".name";
    std::map<std::string, std::size_t> first;
    for (std::size_t i = 0; i < d.count(table); ++i) {
      const std::string name = d.string(key, i);
      const auto [at, inserted] = first.emplace(name, i);
      if (!inserted)
        throw SceneError({d.issue(key, i, "another [[" + std::string(table) + "]] is already called '" + name + "' (" +
                                              table + "[" + std::to_string(at->second) + "]); names must be unique")});
    }
  }
}
// a probe's name becomes its plot, plots/<name>.png (an arc's, plots/arc_rate_<name>.png and
// arc_strain_<name>.png), and a series of results.h5: refused here with the rule scene.name
// follows, so that check sees it instead of a run that fails after its solve
void refuse_names_unfit_for_files(const Document& d) {
  for (const char* table : {"probe", "arc"}) {
    if (!d.declares_array(table)) continue;
    const std::string key = std::string(table) + ".name";
    for (std::size_t i = 0; i < d.count(table); ++i) {
      const std::string& name = d.string(key, i);
      if (const std::string why = file_name_problem(name); !why.empty())
        throw SceneError({d.issue(key, i, text::quoted(name) + " " + why + "; the name becomes the plot file plots/" +
                                              (std::string(table) == "arc" ? "arc_rate_" : "") + "<name>.png, so it must "
                                              "be one plain file name (letters, digits, '_', '-', '.'; at most " +
                                              std::to_string(kMaxFileNameBytes) + " bytes)")});
    }
  }
}
// a [[probe]] named as a series the run records itself ("lambda" and "load" of a static path)
// would be a second series of that name in results.h5, which refuses it when the run starts:
// refused here, naming the run's own series
void refuse_names_the_run_takes(const Document& d, const RunInfo& info) {
  if (!d.declares_array("probe")) return;
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    const std::string& name = d.string("probe.name", i);
    const auto same = std::count_if(info.probes.begin(), info.probes.end(), [&](const Quantity& q) { return q.name == name; });
    if (same < 2) continue;
    // the run's series less one of each name the [[probe]] entries declare
    std::vector<std::string> series;
    for (const Quantity& q : info.probes) series.push_back(q.name);
    for (std::size_t k = 0; k < d.count("probe"); ++k)
      if (const auto at = std::find(series.begin(), series.end(), d.string("probe.name", k)); at != series.end())
        series.erase(at);
    std::string own;
    for (const std::string& n : series) own += (own.empty() ? "" : ", ") + n;
    throw SceneError({d.issue("probe.name", i, "'" + name + "' is the name of a series the run records itself (" + own +
                                                   "); give the probe another name")});
  }
}
}  // namespace

LoadedScene load_scene(const std::string& path, const std::vector<std::string>& overrides, const SceneContext& ctx) {
  return load_scene_text(read_scene_text(path), path, overrides, ctx);
}

LoadedScene load_scene_text(const std::string& text, const std::string& path, const std::vector<std::string>& overrides,
                            const SceneContext& ctx) {
  const Peeked peeked = peek_model_text(text, path);
  refuse_unknown_model(peeked, path, text);
  const ModelKind& kind = kind_or_first(peeked);
  const Document d = validate(kind.schema(), text, path, overrides);
  LoadedScene s;
  s.name = d.string("scene.name");
  if (const std::string why = file_name_problem(s.name); !why.empty())
    throw SceneError({d.issue("scene.name", "'" + s.name + "' " + why +
                                                "; the name is the output folder out/<name>, so it must be one plain "
                                                "folder name (letters, digits, '_', '-', '.'; --out chooses any folder)")});
  s.path = path;
  s.output = read_output(d, kind.camera_keys);
  s.output.camera_path = read_timeline(d, d.number(kind.end_key)).camera;
  refuse_repeated_names(d);
  refuse_names_unfit_for_files(d);
  SceneContext with_report = ctx;  // a shell structure's builder leaves its mesh quality report here
  MeshQualityReport report;
  with_report.mesh_quality = &report;
  with_report.warnings = &s.warnings;
  s.simulation = kind.build(d, path, with_report);
  refuse_names_the_run_takes(d, s.simulation->info());
  if (report.quality.quad_count > 0) s.mesh_quality = std::move(report);
  s.schema = &kind.schema();
  return s;
}

std::string change_live(LoadedScene& scene, const std::string& key, const std::string& value) {
  if (!scene.schema || !scene.simulation) throw std::logic_error("change_live: the scene was not loaded by load_scene");
  Value v;
  try {
    v = validate_live(*scene.schema, key, value);
  } catch (const SceneError& e) {
    return e.what();
  }
  // the schema's kinds map one to one onto LiveValue; monostate never comes back
  const LiveValue typed = std::visit(
      [](auto&& x) -> LiveValue {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, std::monostate>)
          throw std::logic_error("validate_live returned no value");
        else
          return x;
      },
      v);
  return scene.simulation->change_live(key, typed);
}

double estimated_run_bytes(const std::string& path, const std::vector<std::string>& overrides, const SceneContext& ctx) {
  try {
    const std::string text = read_text_or_empty(path);
    const Peeked peeked = peek_model_text(text, path);
    refuse_unknown_model(peeked, path, text);
    const ModelKind& kind = kind_or_first(peeked);
    const Document d = validate_file(kind.schema(), path, overrides);
    return kind.estimated_bytes(d, path, ctx);
  } catch (const SceneError&) {
    return 0.0;
  }
}

namespace {
std::string check_line(const LoadedScene& s) {
  const RunInfo& info = s.simulation->info();
  std::ostringstream out;
  out << s.name << ": valid; effects";
  for (const std::string& e : info.effects) out << ' ' << e;
  out << "; " << info.mesh.point_count() << " drawn points; " << s.simulation->end_description();
  return out.str();
}
// what became of each mesh file (its elements, triangles, directors, named groups), a line each
std::string mesh_import_lines(const LoadedScene& s) {
  std::string out;
  for (const auto& [key, value] : s.simulation->info().settings)
    if (key.rfind("mesh_import", 0) == 0) out += "\n  " + key + ": " + value;
  return out;
}
}  // namespace

std::string check_scene(const std::string& path, const std::vector<std::string>& overrides, const SceneContext& ctx) {
  return check_line(load_scene(path, overrides, ctx));
}

std::string check_scene_report(const std::string& path, const std::vector<std::string>& overrides,
                               const SceneContext& ctx) {
  const LoadedScene s = load_scene(path, overrides, ctx);
  std::string out = check_line(s) + mesh_import_lines(s);
  if (s.mesh_quality) out += "\n" + s.mesh_quality->text();
  while (!out.empty() && out.back() == '\n') out.pop_back();
  for (const std::string& w : s.warnings) out += "\nwarning: " + w;
  return out;
}

}  // namespace ff::scene
