#include "app/study_spec.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/frame/file_name.h"
#include "core/frame/input_file.h"
#include "app/run_session.h"
#include "core/scene/scene.h"
#include "core/scene/schema.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

const scene::Schema& study_schema() {
  using scene::IntRange;
  using scene::Range;
  static const scene::Schema s = [] {
    scene::Schema s;
    s.table("study", "what is varied, what is measured and against what", true)
        .string("study.name", "study name (default: the file name)", std::string())
        .string("study.description", "one line shown in study.md", std::string())
        .string("study.scene", "base scene: bundled name or path relative to this file", std::nullopt)
        .string("study.metric", "summary.json metric whose error is measured", std::nullopt)
        .string_list("study.set", "--set overrides applied to every run (e.g. a shorter end time)",
                     std::vector<std::string>{})
        .choice("study.combine", "grid: every combination of the axes; each: one axis at a time",
                {"grid", "each"}, std::string("grid"))
        .integer("study.repeat", "timing repetitions per variant (median wall time)", 1, IntRange::closed(1, 100));
    s.table_array("vary", "an axis: keys set together to each value, values ordered coarse to fine", 1)
        .string_list("vary.key", "scene keys set to each value (one, or several set together)", std::nullopt)
        .string_list("vary.values", "TOML value texts as for --set: \"8\", \"5e-4\", '\"frozen\"', '[\"elastic\"]'",
                     std::nullopt)
        .string_list("vary.labels", "display names of the values (default: the values)", std::vector<std::string>{});
    s.table_array("variant", "an extra run besides the axes, e.g. a comparator scene")
        .string("variant.label", "its name in the table and plot", std::nullopt)
        .string("variant.scene", "scene (default: the base scene)", std::string())
        .string_list("variant.set", "--set overrides (after study.set)", std::vector<std::string>{});
    s.table("reference", "where the reference value of the metric comes from", true)
        .choice("reference.kind",
                "finest: the run with every axis at its last value; value: a number (analytic or published); "
                "table: a reference CSV interpolated at `at`; scene: a run of another scene",
                {"finest", "value", "table", "scene"}, std::nullopt)
        .number("reference.value", "kind value: the reference value", 0.0)
        .string("reference.source", "citation shown in study.md (required for value and table)", std::string())
        .string("reference.file", "kind table: CSV path relative to this file", std::string())
        .string("reference.x_column", "kind table: abscissa column", std::string())
        .string("reference.y_column", "kind table: value column", std::string())
        .number("reference.x_scale", "kind table: abscissa multiplier (e.g. P/Pmax -> P)", 1.0, Range::positive())
        .number("reference.at", "kind table: abscissa (after x_scale) of the reference value", 0.0)
        .string("reference.scene", "kind scene: scene (default: the base scene)", std::string())
        .string_list("reference.set", "kind scene: --set overrides (after study.set)", std::vector<std::string>{});
    return s;
  }();
  return s;
}

/// Splits at `sep` outside [...], {...} and quotes.
std::vector<std::string> split_top(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  int depth = 0;
  char quote = 0;
  for (char c : s) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == sep && depth == 0) {
      out.push_back(cur);
      cur.clear();
      continue;
    }
    cur += c;
  }
  out.push_back(cur);
  return out;
}

std::string resolve_relative(const std::string& name, const fs::path& base_dir) {
  const fs::path rel = base_dir / name;
  if (!name.empty() && fs::path(name).is_relative() && fs::is_regular_file(rel)) return rel.string();
  return resolve_scene(name);
}

StudyVariant make_variant(const StudySpec& spec, const std::vector<std::size_t>& pick,
                          const std::vector<bool>& used) {
  StudyVariant v;
  v.scene = spec.scene;
  v.overrides = spec.base_overrides;
  for (std::size_t a = 0; a < spec.axes.size(); ++a) {
    const StudyAxis& axis = spec.axes[a];
    if (!used[a]) {
      v.axis_labels.push_back("");
      continue;
    }
    for (const std::string& k : axis.keys) v.overrides.push_back(k + "=" + axis.values[pick[a]]);
    v.axis_labels.push_back(axis.label(pick[a]));
    v.label += (v.label.empty() ? "" : ", ") + axis.name() + "=" + axis.label(pick[a]);
  }
  if (v.label.empty()) v.label = "base";
  return v;
}

}  // namespace

std::string StudyAxis::name() const {
  std::string n;
  for (const std::string& k : keys) n += (n.empty() ? "" : "+") + k;
  return n;
}

std::string StudyAxis::label(std::size_t i) const {
  if (i < labels.size()) return labels[i];
  std::string v = values[i];
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) v = v.substr(1, v.size() - 2);
  return v;
}

std::vector<StudyVariant> StudySpec::variants() const {
  std::vector<StudyVariant> out;
  const std::size_t n = axes.size();
  if (grid) {
    // odometer over the axes, the last axis fastest
    std::vector<std::size_t> pick(n, 0);
    const std::vector<bool> used(n, true);
    while (n > 0) {
      out.push_back(make_variant(*this, pick, used));
      std::size_t a = n;
      while (a > 0 && ++pick[a - 1] == axes[a - 1].values.size()) pick[--a] = 0;
      if (a == 0) break;
    }
  } else {
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t i = 0; i < axes[a].values.size(); ++i) {
        std::vector<std::size_t> pick(n, 0);
        std::vector<bool> used(n, false);
        pick[a] = i;
        used[a] = true;
        out.push_back(make_variant(*this, pick, used));
      }
  }
  for (StudyVariant v : extra) {
    v.axis_labels.assign(n, "");
    out.push_back(std::move(v));
  }
  return out;
}

StudyVariant StudySpec::finest() const {
  std::vector<std::size_t> pick;
  for (const StudyAxis& a : axes) pick.push_back(a.values.size() - 1);
  return make_variant(*this, pick, std::vector<bool>(axes.size(), true));
}

std::optional<StudyVariant> StudySpec::reference_run() const {
  if (reference.kind == StudyReference::Kind::finest) return finest();
  if (reference.kind == StudyReference::Kind::scene)
    return StudyVariant{"reference", reference.scene, reference.overrides, {}};
  return std::nullopt;
}

bool is_study_file(const std::string& path) {
  std::string text;
  if (fs::path(path).extension() != ".toml" ||
      !read_input_file(path, &text, kMaxTextInputBytes, kTextInputBound, nullptr))
    return false;  // a scene, or unreadable: what reads it next says why
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto b = line.find_first_not_of(" \t");
    if (b != std::string::npos && line.compare(b, 7, "[study]") == 0) return true;
  }
  return false;
}

StudySpec read_study_file(const std::string& path) {
  const scene::Document d = scene::validate_file(study_schema(), path, {});
  const fs::path dir = fs::path(path).parent_path();
  std::vector<scene::Issue> issues;
  const auto scene_at = [&](const std::string& key, const std::string& name) -> std::string {
    try {
      return resolve_relative(name, dir);
    } catch (const InputError& e) {
      issues.push_back(d.issue(key, e.what()));
      return name;
    }
  };
  StudySpec s;
  s.name = d.string("study.name").empty() ? fs::path(path).stem().string() : d.string("study.name");
  if (const std::string why = file_name_problem(s.name); !why.empty())
    issues.push_back(d.issue(d.string("study.name").empty() ? "study.scene" : "study.name",
                             "the study name '" + s.name + "' " + why +
                                 "; it names the output folder out/study/<name>, so it must be one plain folder name "
                                 "(--out chooses any folder)"));
  s.description = d.string("study.description");
  s.scene = scene_at("study.scene", d.string("study.scene"));
  s.metric = d.string("study.metric");
  s.base_overrides = d.strings("study.set");
  s.grid = d.string("study.combine") == "grid";
  s.repeat = static_cast<int>(d.integer("study.repeat"));
  // each override the study file writes, with the line it is written at
  const auto origin = [&](const std::string& text, const scene::Issue& at) {
    s.origins.push_back({text, at.file, at.line, at.column, at.key});
  };
  for (const std::string& o : d.strings("study.set")) origin(o, d.issue("study.set", ""));
  for (std::size_t i = 0; i < d.count("vary"); ++i) {
    StudyAxis a{d.strings("vary.key", i), d.strings("vary.values", i), d.strings("vary.labels", i)};
    for (const std::string& k : a.keys)
      for (const std::string& v : a.values) origin(k + "=" + v, d.issue("vary.values", i, ""));
    if (a.keys.empty()) issues.push_back(d.issue("vary.key", i, "name at least one scene key"));
    if (a.values.empty()) issues.push_back(d.issue("vary.values", i, "give at least one value"));
    if (!a.labels.empty() && a.labels.size() != a.values.size())
      issues.push_back(d.issue("vary.labels", i,
                               "has " + std::to_string(a.labels.size()) + " labels for " +
                                   std::to_string(a.values.size()) + " values"));
    s.axes.push_back(std::move(a));
  }
  for (std::size_t i = 0; i < d.count("variant"); ++i) {
    StudyVariant v;
    v.label = d.string("variant.label", i);
    v.scene = d.string("variant.scene", i).empty() ? s.scene : scene_at("variant.scene", d.string("variant.scene", i));
    v.overrides = s.base_overrides;
    for (const std::string& o : d.strings("variant.set", i)) {
      v.overrides.push_back(o);
      origin(o, d.issue("variant.set", i, ""));
    }
    s.extra.push_back(std::move(v));
  }
  StudyReference& r = s.reference;
  const std::string kind = d.string("reference.kind");
  r.source = d.string("reference.source");
  if (kind == "finest") {
    r.kind = StudyReference::Kind::finest;
  } else if (kind == "value") {
    r.kind = StudyReference::Kind::value;
    if (!d.present("reference.value")) issues.push_back(d.issue("reference.kind", "kind value needs reference.value"));
    r.value = d.number("reference.value");
  } else if (kind == "table") {
    r.kind = StudyReference::Kind::table;
    for (const char* k : {"reference.file", "reference.x_column", "reference.y_column", "reference.at"})
      if (!d.present(k)) issues.push_back(d.issue("reference.kind", std::string("kind table needs ") + k));
    r.file = (dir / d.string("reference.file")).string();
    r.x_column = d.string("reference.x_column");
    r.y_column = d.string("reference.y_column");
    r.x_scale = d.number("reference.x_scale");
    r.at = d.number("reference.at");
  } else {
    r.kind = StudyReference::Kind::scene;
    r.scene = d.string("reference.scene").empty() ? s.scene : scene_at("reference.scene", d.string("reference.scene"));
    r.overrides = s.base_overrides;
    for (const std::string& o : d.strings("reference.set")) {
      r.overrides.push_back(o);
      origin(o, d.issue("reference.set", ""));
    }
  }
  if ((kind == "value" || kind == "table") && r.source.empty())
    issues.push_back(d.issue("reference.source", "say where the reference value comes from (kind " + kind + ")"));
  if (!issues.empty()) throw scene::SceneError(issues);
  return s;
}

void locate_in_study_file(const StudySpec& spec, std::vector<scene::Issue>& issues) {
  static const std::string kSet = "--set ";
  for (scene::Issue& i : issues) {
    if (i.file.rfind(kSet, 0) != 0) continue;
    const std::string text = i.file.substr(kSet.size());
    for (const OverrideOrigin& o : spec.origins)
      if (o.override_text == text) {
        i.message += " (" + text + ", from " + o.key + ")";
        i.file = o.file;
        i.line = o.line;
        i.column = o.column;
        break;
      }
  }
}

std::string locate_in_study_file(const StudySpec& spec, const std::string& message) {
  std::istringstream in(message);
  std::string line, out;
  while (std::getline(in, line)) {
    for (const OverrideOrigin& o : spec.origins) {
      const std::string prefix = "--set " + o.override_text + ": ";
      if (line.rfind(prefix, 0) != 0) continue;
      line = o.file + ":" + std::to_string(o.line) + ":" + std::to_string(o.column) + ": " + line.substr(prefix.size()) +
             " (" + o.override_text + ", from " + o.key + ")";
      break;
    }
    out += (out.empty() ? "" : "\n") + line;
  }
  return out;
}

StudyAxis parse_vary(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw InputError("--vary needs KEY=V1,V2,... (or KEY1+KEY2=V1,V2 to set keys together), got '" + spec + "'");
  StudyAxis a;
  a.keys = split_top(spec.substr(0, eq), '+');
  a.values = split_top(spec.substr(eq + 1), ',');
  for (const std::string& k : a.keys)
    if (k.empty()) throw InputError("--vary '" + spec + "': empty key");
  for (const std::string& v : a.values)
    if (v.empty()) throw InputError("--vary '" + spec + "': empty value");
  return a;
}

StudyReference parse_reference(const std::string& text) {
  StudyReference r;
  if (text == "finest") return r;
  if (text.rfind("scene:", 0) == 0) {
    r.kind = StudyReference::Kind::scene;
    r.scene = resolve_scene(text.substr(6));
    return r;
  }
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
    throw InputError("--reference must be 'finest', a number, or 'scene:NAME', got '" + text + "'");
  r.kind = StudyReference::Kind::value;
  r.value = v;
  r.source = "--reference " + text;
  return r;
}

std::string study_reference_markdown() { return study_schema().markdown_reference(); }

std::vector<std::pair<std::string, std::string>> bundled_studies() {
  std::vector<std::pair<std::string, std::string>> out;
  const fs::path dir = fs::path(scene_dir()).parent_path() / "studies";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".toml") out.emplace_back(e.path().stem().string(), e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ff::app
