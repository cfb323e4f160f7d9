#pragma once
/// \file study_spec.h
/// What a study runs: a base scene, axes of scene keys to vary (combined as a grid or one at a
/// time), extra variants (e.g. another scene as a comparator), the metric, and where its
/// reference value comes from. Built either from a study file (assets/studies/*.toml, validated
/// like a scene: bad keys are reported as file:line:column) or from `flexframe study` options.

#include <optional>
#include <string>
#include <vector>

namespace ff::scene {
struct Issue;
}

namespace ff::app {

/// Where in a study file an override a variant gets came from (vary values, study.set,
/// variant.set, reference.set), so that a scene's refusal of it can name the study file's line.
struct OverrideOrigin {
  std::string override_text;  ///< "part[0].n1=8", as passed to the scene
  std::string file;           ///< the study file
  int line = 0, column = 0;
  std::string key;            ///< the study key it was written at ("vary[0].values")
};

/// One varied quantity: `keys` are set together to each value (e.g. mesh.n1 and mesh.n2).
/// Values are TOML value texts as for --set ("8", "5e-4", "\"frozen\"", "[\"elastic\"]").
/// Order them coarse to fine: the last value is the "finest".
struct StudyAxis {
  std::vector<std::string> keys;
  std::vector<std::string> values;
  std::vector<std::string> labels;  ///< display names of the values; empty = the values
  std::string name() const;         ///< "part[0].n1+part[0].n2"
  std::string label(std::size_t i) const;
};

/// One run of the study.
struct StudyVariant {
  std::string label;                   ///< "solver.dt=5e-4, solver.policy=frozen"
  std::string scene;                   ///< resolved scene path
  std::vector<std::string> overrides;  ///< --set arguments (base ones first)
  std::vector<std::string> axis_labels;  ///< value label per axis ("" for extra variants)
  /// The same scene with the same overrides (labels aside).
  bool same_run(const StudyVariant& other) const { return scene == other.scene && overrides == other.overrides; }
};

/// Where the error of each variant is measured from.
struct StudyReference {
  enum class Kind { finest, value, table, scene } kind = Kind::finest;
  double value = 0.0;        ///< kind value
  std::string source;        ///< citation / description shown in the table
  // kind table: y(x = at) interpolated linearly in a reference CSV
  std::string file, x_column, y_column;
  double x_scale = 1.0, at = 0.0;
  // kind scene: one run of another scene (or the base scene) with these overrides
  std::string scene;
  std::vector<std::string> overrides;
};

struct StudySpec {
  std::string name, description;
  std::string scene;                   ///< resolved base scene path
  std::vector<std::string> base_overrides;
  std::vector<StudyAxis> axes;
  bool grid = true;                    ///< all combinations; false: each axis alone (others at the base)
  std::vector<StudyVariant> extra;     ///< run besides the axes (comparators)
  std::string metric;
  StudyReference reference;
  int repeat = 1;                      ///< timing repetitions per variant (median)
  std::vector<OverrideOrigin> origins;  ///< study-file overrides and their lines (none from options)

  /// Every run, in order: the axes' combinations, then the extra variants.
  std::vector<StudyVariant> variants() const;
  /// The run that defines the reference for kind finest (every axis at its last value).
  StudyVariant finest() const;
  /// The run the reference comes from (kinds finest and scene); none for value and table.
  std::optional<StudyVariant> reference_run() const;
};

/// True when `path` is a TOML file with a [study] table.
bool is_study_file(const std::string& path);
/// Reads and validates a study file; throws scene::SceneError (file:line:column, key) on bad input.
/// Scenes are bundled names or paths relative to the study file.
StudySpec read_study_file(const std::string& path);
/// Issues a scene raised about an override ("--set mesh.n1=abc") that came from the study file
/// are moved to the study file's line and column of that entry, the --set text kept in the
/// message; other issues are left as they are.
void locate_in_study_file(const StudySpec& spec, std::vector<scene::Issue>& issues);
/// The same for a refusal already written as text (a variant run in its own process): each line
/// "--set <override>: ..." of an override from the study file starts with its file:line:column.
std::string locate_in_study_file(const StudySpec& spec, const std::string& message);

/// Parses "KEY[+KEY2]=V1,V2,..." (commas inside [...] or quotes do not split); throws InputError.
StudyAxis parse_vary(const std::string& spec);
/// Parses --reference: "finest", a number, or "scene:NAME_OR_PATH"; throws InputError.
StudyReference parse_reference(const std::string& text);
/// The study file key reference as markdown (docs/guide/studies.md).
std::string study_reference_markdown();
/// Bundled studies (assets/studies), name -> path, sorted.
std::vector<std::pair<std::string, std::string>> bundled_studies();

}  // namespace ff::app
