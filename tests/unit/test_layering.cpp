// The layers stay visible (docs/architecture.md, core/CMakeLists.txt): every #include of the
// project's own headers and of the big libraries is checked against the table of what each part
// may use. A header pulled from a higher layer, VTK in core or a model in render fails here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

namespace fs = std::filesystem;

namespace {
// part -> the project folders its files may include (besides its own)
const std::map<std::string, std::set<std::string>> kAllowed = {
    {"core/frame", {}},
    {"core/lie", {}},
    {"core/mesh", {}},
    {"core/assembly", {"core/lie"}},
    {"core/solve", {"core/frame"}},
    {"core/model", {"core/frame"}},
    {"core/shell", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model"}},
    {"core/hubbeam", {"core/frame", "core/solve", "core/model"}},
    {"core/scene", {"core/frame", "core/lie", "core/mesh", "core/assembly", "core/solve", "core/model", "core/shell",
                    "core/hubbeam"}},
    {"render", {"core/frame"}},
};
// library headers a part must not include, by prefix
const std::map<std::string, std::vector<std::string>> kForbidden = {
    {"core", {"vtk", "imgui", "GLFW", "H5", "hdf5", "assimp", "nlohmann", "CLI/"}},
    {"render", {"H5", "hdf5", "imgui", "GLFW", "toml++", "nlohmann"}},
};

std::string part_of(const std::string& rel) {  // "core/shell/cb_shell.cpp" -> "core/shell"
  const auto first = rel.find('/');
  if (rel.compare(0, first, "core") == 0) return rel.substr(0, rel.find('/', first + 1));
  return rel.substr(0, first);
}
}  // namespace

TEST(Layering, IncludesFollowTheLayers) {
  const fs::path root(FF_SOURCE_DIR);
  const std::regex include(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  int files = 0;
  for (const char* top : {"core", "render"})
    for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
      const std::string ext = entry.path().extension().string();
      if (ext != ".h" && ext != ".cpp") continue;
      ++files;
      const std::string rel = fs::relative(entry.path(), root).generic_string();
      const std::string part = part_of(rel);
      std::ifstream in(entry.path());
      std::string line;
      int n = 0;
      while (std::getline(in, line)) {
        ++n;
        std::smatch m;
        if (!std::regex_search(line, m, include)) continue;
        const std::string inc = m[1];
        const std::string where = rel + ":" + std::to_string(n) + " includes " + inc;
        for (const std::string& bad : kForbidden.at(top)) EXPECT_NE(inc.rfind(bad, 0), 0u) << where;
        if (inc.rfind("toml++", 0) == 0) EXPECT_EQ(part, "core/scene") << where << " (only the scene layer reads TOML)";
        if (inc.rfind("core/", 0) != 0 && inc.rfind("render/", 0) != 0 && inc.rfind("app/", 0) != 0) continue;
        const std::string target = part_of(inc);
        if (target == part) continue;
        const auto allowed = kAllowed.find(part);
        ASSERT_NE(allowed, kAllowed.end()) << rel << ": part " << part << " is not in the layering table";
        EXPECT_TRUE(allowed->second.count(target)) << where << " (" << part << " may not use " << target << ")";
      }
    }
  EXPECT_GT(files, 50);
}
