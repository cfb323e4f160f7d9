// The layers stay visible (docs/architecture.md, core/CMakeLists.txt): every #include of the
// project's own headers and of the big libraries is checked against the table of what each part
// may use. A header pulled from a higher layer, VTK in core or a model in render fails here; so
// does, inside the scene layer, a file that includes one of a higher level (the registry from a
// shared helper, say), and any include cycle between two files of the project.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <vector>

namespace fs = std::filesystem;

namespace {
// part -> the project folders its files may include (besides its own)
const std::map<std::string, std::set<std::string>> kAllowed = {
    {"core/frame", {}},
    {"core/lie", {}},
    {"core/mesh", {"core/frame"}},
    {"core/assembly", {"core/lie"}},
    {"core/solve", {"core/frame"}},
    {"core/model", {"core/frame"}},
    {"core/shell", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model"}},
    {"core/hubbeam", {"core/frame", "core/solve", "core/model"}},
    {"core/scene", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model", "core/shell",
                    "core/hubbeam"}},
    {"render", {"core/frame"}},
    // results files, movies and mesh import: frames and meshes, nothing of the models, the
    // solvers, the renderer or the rest of the app
    {"app/io", {"core/frame", "core/mesh"}},
    // the window: the scene layer and models it edits and runs, the renderer, the run's outputs
    {"app/gui", {"core/frame", "core/mesh", "core/model", "core/scene", "render", "app/io", "app"}},
    // the verbs and pipelines that wire the rest together; the window is started from the command
    // line only (command_line.cpp, through gui_app.h)
    {"app", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model", "core/shell",
             "core/hubbeam", "core/scene", "render", "app/io", "app/bench"}},
    // `flexframe bench`: measures what the rest offers, and is used by the command line alone
    {"app/bench", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model", "core/shell",
                   "core/hubbeam", "core/scene", "render", "app/io", "app"}},
};
// part -> single headers of a part it may include though not the part (the interface it serves)
const std::map<std::string, std::set<std::string>> kAllowedHeaders = {
    // the mesh importer is the reader a SceneContext carries (ff::io::scene_context())
    {"app/io", {"core/scene/mesh_file.h", "core/scene/scene_context.h"}},
    {"app", {"app/gui/gui_app.h"}},
};
// library headers a part must not include, by prefix
const std::map<std::string, std::vector<std::string>> kForbidden = {
    {"core", {"vtk", "imgui", "GLFW", "H5", "hdf5", "assimp", "gmsh", "nlohmann", "CLI/"}},
    {"render", {"H5", "hdf5", "imgui", "GLFW", "toml++", "nlohmann", "gmsh"}},
    {"app/io", {"vtk", "imgui", "GLFW", "toml++", "nlohmann", "CLI/"}},
    // VTK is render's, HDF5 app/io's, the window's libraries app/gui's
    {"app/gui", {"vtk", "H5", "hdf5", "toml++"}},
    {"app", {"vtk", "H5", "hdf5", "imgui", "GLFW", "toml++"}},
    {"app/bench", {"vtk", "H5", "hdf5", "imgui", "GLFW", "toml++"}},
};
const std::vector<std::string> kChecked = {"core", "render", "app"};

// The scene layer's own order (docs/architecture.md): a file may include files of its level or
// below. Units are file stems (x.h and x.cpp are one unit); a new file needs a row here.
enum SceneLevel { kSchema, kContext, kSharedKeys, kModels, kRegistry, kEditing };
const char* const kSceneLevelNames[] = {"schema", "context", "shared keys", "models", "registry", "editing"};
const std::map<std::string, SceneLevel> kSceneLevels = {
    // TOML -> a validated Document, with located errors; knows no model
    {"schema", kSchema},
    {"schema_document", kSchema},
    {"schema_validate", kSchema},
    {"schema_text", kSchema},
    {"schema_value", kSchema},
    // what the program around hands to a build
    {"mesh_file", kContext},
    {"scene_context", kContext},
    // keys and reading every model (or several) shares
    {"scene_common", kSharedKeys},
    {"output_settings", kSharedKeys},
    {"timeline", kSharedKeys},
    {"node_selection", kSharedKeys},
    {"mesh_generator_keys", kSharedKeys},
    {"shell_boundary", kSharedKeys},
    {"structure_parts", kSharedKeys},
    {"mesh_quality_report", kSharedKeys},
    {"shell_structure_scene", kSharedKeys},
    {"reference_csv", kSharedKeys},
    // one file per model: its schema and builder
    {"hub_beam_scene", kModels},
    {"shell_scene", kModels},
    {"shell_dynamic_scene", kModels},
    {"shell_eigen_scene", kModels},
    // model_kinds() and load_scene
    {"scene", kRegistry},
    // what a scene's names select, for check --picture (reads a scene as the registry does)
    {"scene_selections", kRegistry},
    // the coarser twins of a scene whose metrics give the error bars (reads a scene as the registry does)
    {"discretization_twins", kRegistry},
    // writing edited scenes back
    {"scene_edit", kEditing},
};

std::string part_of(const std::string& rel) {  // "core/shell/cb_shell.cpp" -> "core/shell"
  const auto first = rel.find('/');
  if (rel.compare(0, first, "core") == 0) return rel.substr(0, rel.find('/', first + 1));
  if (rel.rfind("app/io/", 0) == 0) return "app/io";
  if (rel.rfind("app/gui/", 0) == 0) return "app/gui";
  if (rel.rfind("app/bench/", 0) == 0) return "app/bench";
  return rel.substr(0, first);
}

std::string unit_of(const std::string& rel) {  // "core/scene/scene.cpp" -> "core/scene/scene"
  return rel.substr(0, rel.rfind('.'));
}

bool is_project_header(const std::string& inc) {
  return inc.rfind("core/", 0) == 0 || inc.rfind("render/", 0) == 0 || inc.rfind("app/", 0) == 0;
}

struct Include {
  std::string file;  // relative to the source root
  int line;
  std::string header;
};

// every #include of the .h and .cpp files under `top` (relative to the source root)
std::vector<Include> includes_under(const fs::path& root, const std::string& top, int* files = nullptr) {
  const std::regex include(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  std::vector<Include> out;
  for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".h" && ext != ".cpp") continue;
    if (files) ++*files;
    const std::string rel = fs::relative(entry.path(), root).generic_string();
    std::ifstream in(entry.path());
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      ++n;
      std::smatch m;
      if (std::regex_search(line, m, include)) out.push_back({rel, n, m[1]});
    }
  }
  return out;
}

// The level of a scene-layer unit, or a failure naming the file that has no row.
const SceneLevel* scene_level(const std::string& rel) {
  const std::string prefix = "core/scene/";
  if (rel.rfind(prefix, 0) != 0) return nullptr;
  const std::string stem = unit_of(rel).substr(prefix.size());
  const auto it = kSceneLevels.find(stem);
  return it == kSceneLevels.end() ? nullptr : &it->second;
}
}  // namespace

TEST(Layering, IncludesFollowTheLayers) {
  const fs::path root(FF_SOURCE_DIR);
  int files = 0;
  for (const std::string& top : kChecked)
    for (const Include& i : includes_under(root, top, &files)) {
      const std::string part = part_of(i.file);
      const std::string where = i.file + ":" + std::to_string(i.line) + " includes " + i.header;
      for (const std::string& bad : kForbidden.at(part.rfind("core", 0) == 0 ? "core" : part))
        EXPECT_NE(i.header.rfind(bad, 0), 0u) << where;
      if (i.header.rfind("toml++", 0) == 0) { EXPECT_EQ(part, "core/scene") << where << " (only the scene layer reads TOML)"; }
      if (!is_project_header(i.header)) continue;
      const std::string target = part_of(i.header);
      if (target == part) continue;
      const auto allowed = kAllowed.find(part);
      ASSERT_NE(allowed, kAllowed.end()) << i.file << ": part " << part << " is not in the layering table";
      const auto headers = kAllowedHeaders.find(part);
      const bool allowed_header = headers != kAllowedHeaders.end() && headers->second.count(i.header);
      EXPECT_TRUE(allowed->second.count(target) || allowed_header)
          << where << " (" << part << " may not use " << target << ")";
    }
  EXPECT_GT(files, 50);
}

TEST(Layering, SceneFilesIncludeOnlyTheirLevelOrBelow) {
  const fs::path root(FF_SOURCE_DIR);
  int checked = 0;
  for (const Include& i : includes_under(root, "core/scene")) {
    const SceneLevel* from = scene_level(i.file);
    ASSERT_NE(from, nullptr) << i.file << " has no level in kSceneLevels (tests/unit/test_layering.cpp)";
    if (i.header.rfind("core/scene/", 0) != 0) continue;
    const SceneLevel* to = scene_level(i.header);
    ASSERT_NE(to, nullptr) << i.file << ":" << i.line << " includes " << i.header << ", which has no level";
    EXPECT_LE(*to, *from) << i.file << ":" << i.line << " (" << kSceneLevelNames[*from] << ") includes " << i.header
                          << " (" << kSceneLevelNames[*to] << "), a higher level of the scene layer";
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

// A cycle of includes between units (x.h and x.cpp together) anywhere in core/, render/ or app/:
// two files that need each other are one concept in two homes, or a helper that reaches back up
// to its caller.
TEST(Layering, NoIncludeCycles) {
  const fs::path root(FF_SOURCE_DIR);
  std::map<std::string, std::set<std::string>> uses;  // unit -> units it includes
  for (const char* top : {"core", "render", "app"})
    for (const Include& i : includes_under(root, top)) {
      if (!is_project_header(i.header)) continue;
      const std::string from = unit_of(i.file), to = unit_of(i.header);
      if (from != to) uses[from].insert(to);
    }
  // depth-first search; a unit met again while on the stack closes a cycle
  std::map<std::string, int> state;  // 0 unseen, 1 on the stack, 2 done
  std::vector<std::string> stack;
  std::vector<std::string> cycles;
  std::function<void(const std::string&)> visit = [&](const std::string& u) {
    state[u] = 1;
    stack.push_back(u);
    for (const std::string& v : uses[u]) {
      if (state[v] == 1) {
        std::string c;
        for (auto it = std::find(stack.begin(), stack.end(), v); it != stack.end(); ++it) c += *it + " -> ";
        cycles.push_back(c + v);
      } else if (state[v] == 0) {
        visit(v);
      }
    }
    stack.pop_back();
    state[u] = 2;
  };
  std::vector<std::string> units;
  for (const auto& [u, _] : uses) units.push_back(u);
  for (const std::string& u : units)
    if (state[u] == 0) visit(u);
  for (const std::string& c : cycles) ADD_FAILURE() << "include cycle: " << c;
  EXPECT_GT(uses.size(), 50u);
}
