// Scripted scenes end to end: two runs of the same scene give the same results.h5 apart from
// timing (every data set and attribute compared byte for byte through the HDF5 C API), replay
// follows the stored camera path unless --camera is given, and a bad timeline exits 2 naming
// file:line and key.

#include <gtest/gtest.h>
#include <hdf5.h>
#include <nlohmann/json.hpp>

#include <map>
#include <set>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

// attributes that measure the wall clock, not the simulation
const std::set<std::string> kTimingAttributes = {"wall_time_s"};

struct H5Contents {
  std::map<std::string, std::string> datasets;    // path -> type, shape and raw bytes
  std::map<std::string, std::string> attributes;  // object path + "@" + name -> type and raw bytes
};

std::string type_text(hid_t type) {
  return std::to_string(H5Tget_class(type)) + "/" + std::to_string(H5Tget_size(type));
}

void read_attributes(hid_t obj, const std::string& path, H5Contents* c) {
  H5O_info_t info;
  H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS);
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const hid_t a = H5Aopen_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT);
    char name[256] = {0};
    H5Aget_name(a, sizeof name, name);
    const hid_t type = H5Aget_type(a), space = H5Aget_space(a);
    std::string bytes = type_text(type) + "|";
    if (H5Tis_variable_str(type) > 0) {
      // read with the stored type (UTF-8 variable-length strings), scalar or an array of them
      std::vector<char*> s(static_cast<std::size_t>(std::max<hssize_t>(1, H5Sget_simple_extent_npoints(space))));
      EXPECT_GE(H5Aread(a, type, s.data()), 0) << path << "@" << name;
      for (char* p : s) {
        bytes += std::string(p ? p : "") + '\0';
        H5free_memory(p);
      }
    } else {
      std::string buf(static_cast<std::size_t>(H5Aget_storage_size(a)), '\0');
      EXPECT_GE(H5Aread(a, type, buf.data()), 0) << path << "@" << name;
      bytes += buf;
    }
    c->attributes[path + "@" + name] = bytes;
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(a);
  }
}

herr_t visit(hid_t root, const char* name, const H5O_info_t* info, void* data) {
  auto* c = static_cast<H5Contents*>(data);
  const std::string path = std::string("/") + (std::string(name) == "." ? "" : name);
  const hid_t obj = H5Oopen(root, name, H5P_DEFAULT);
  read_attributes(obj, path, c);
  if (info->type == H5O_TYPE_DATASET) {
    const hid_t type = H5Dget_type(obj), space = H5Dget_space(obj);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::string shape;
    hsize_t dims[8];
    const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
    for (int k = 0; k < rank; ++k) shape += std::to_string(dims[k]) + ",";
    std::string bytes = type_text(type) + "|" + shape + "|";
    if (H5Tis_variable_str(type) > 0) {
      std::vector<char*> s(static_cast<std::size_t>(n));
      EXPECT_GE(H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()), 0) << path;
      for (char* p : s) bytes += std::string(p ? p : "") + '\0';
      H5Dvlen_reclaim(type, space, H5P_DEFAULT, s.data());
    } else {
      std::string buf(static_cast<std::size_t>(n) * H5Tget_size(type), '\0');
      EXPECT_GE(H5Dread(obj, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()), 0) << path;
      bytes += buf;
    }
    c->datasets[path] = bytes;
    H5Sclose(space);
    H5Tclose(type);
  }
  H5Oclose(obj);
  return 0;
}

H5Contents read_h5(const std::string& file) {
  H5Contents c;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  if (f < 0) return c;
  H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_INC, visit, &c, H5O_INFO_BASIC);
  H5Fclose(f);
  return c;
}

// the error bars' JSON (a string attribute: its type, '|', the text, a NUL) without the wall times
// of the twins and the run, which differ between two runs like every other timing
nlohmann::json error_bars_without_timing(const std::string& bytes) {
  const std::size_t from = bytes.find('|') + 1;
  nlohmann::json j = nlohmann::json::parse(bytes.substr(from, bytes.find('\0', from) - from));
  j.erase("cost");
  for (auto& twin : j["twins"]) {
    twin.erase("wall_time_s");
    twin["metrics"].erase("wall_per_sim_second");
  }
  return j;
}

// runs `args` twice into two folders and compares the results.h5 files
void expect_identical_runs(const std::vector<std::string>& args) {
  const std::string dir = fresh_test_dir();
  for (const char* k : {"a", "b"}) {
    std::vector<std::string> a = args;
    a.insert(a.end(), {"--out", dir + "/" + k, "--no-frames", "--no-plots", "--quiet"});
    const ProcResult r = run_flexframe(a, dir + "/run_" + k, "", 300.0);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }
  const H5Contents a = read_h5(dir + "/a/results.h5"), b = read_h5(dir + "/b/results.h5");
  // the whole file: frames, step log, mesh, run description, outcome, metrics, provenance
  EXPECT_GE(a.datasets.size(), 20u);
  EXPECT_GE(a.attributes.size(), 10u);
  EXPECT_GT(a.datasets.count("/frames/points"), 0u);
  EXPECT_GT(a.attributes.count("/outcome@wall_time_s"), 0u);
  ASSERT_EQ(a.datasets.size(), b.datasets.size());
  for (const auto& [path, bytes] : a.datasets) {
    ASSERT_TRUE(b.datasets.count(path)) << path;
    EXPECT_TRUE(bytes == b.datasets.at(path)) << "data set " << path << " differs between two runs";
  }
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  int timing = 0;
  for (const auto& [key, bytes] : a.attributes) {
    ASSERT_TRUE(b.attributes.count(key)) << key;
    const std::string name = key.substr(key.find('@') + 1);
    if (kTimingAttributes.count(name) || name.find("wall_per_sim_second") != std::string::npos) {
      ++timing;
      continue;
    }
    if (name == "error_bars") {  // the twins are as deterministic as the run: everything but their clocks
      EXPECT_EQ(error_bars_without_timing(bytes), error_bars_without_timing(b.attributes.at(key)));
      ++timing;
      continue;
    }
    EXPECT_TRUE(bytes == b.attributes.at(key)) << "attribute " << key << " differs between two runs";
  }
  EXPECT_GE(timing, 1);
}

TEST(CliTimeline, HubBeamRunsAreIdentical) { expect_identical_runs({"run", "hub_beam_timeline"}); }

TEST(CliTimeline, ShellDynamicRunsAreIdentical) {
  expect_identical_runs({"run", "double_pendulum_shells", "--set", "solver.end=0.005"});
}

// the run stores the scene text; replay reads its [[timeline]] and moves the camera along it:
// its first frame is the path's first key (as --camera gives it), its last is not
TEST(CliTimeline, ReplayFollowsTheCameraPath) {
  const std::string dir = fresh_test_dir();
  ProcResult r = run_flexframe({"run", "hub_beam_timeline", "--out", dir + "/run", "--no-frames", "--no-plots", "--quiet"},
                               dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  auto replay = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> a = {"replay", dir + "/run", "--out", dir + "/" + out, "--frame-every", "25",
                                  "--no-plots", "--size", "320x240"};
    a.insert(a.end(), extra.begin(), extra.end());
    const ProcResult p = run_flexframe(a, dir + "/" + out);
    EXPECT_EQ(p.exit_code, 0) << p.describe();
    return pngs_in(dir + "/" + out + "/frames");
  };
  const std::vector<std::string> path = replay("path", {});
  const std::vector<std::string> fixed = replay("fixed", {"--camera", "-90,60"});
  ASSERT_GE(path.size(), 3u);
  ASSERT_EQ(path.size(), fixed.size());
  EXPECT_EQ(render::test::file_bytes(path.front()), render::test::file_bytes(fixed.front())) << "the path starts at its first key";
  EXPECT_NE(render::test::file_bytes(path.back()), render::test::file_bytes(fixed.back())) << "the camera did not move along the path";
  EXPECT_NE(render::test::file_bytes(path[1]), render::test::file_bytes(fixed[1]));
}

TEST(CliTimeline, BadTimelineExits2AtFileLineAndKey) {
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/bad.toml";
  std::string text = read_text(scene_path("hub_beam_timeline"));
  text += "\n[[timeline]]\nat = 2.0\nspin = 3\n";  // after the last entry (at = 2.5): also out of order
  write_text(scene, text);
  const int line = static_cast<int>(std::count(text.begin(), text.end(), '\n'));  // `spin` is the last line
  const ProcResult r = run_flexframe({"run", scene, "--out", dir + "/out", "--quiet"}, dir + "/run");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("bad.toml:" + std::to_string(line)), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("timeline[3].spin"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir + "/out/results.h5"));
  // a camera key outside the run: the check names the key too
  write_text(scene, read_text(scene_path("hub_beam_timeline")) + "\n[[timeline]]\nat = 3.0\ncamera = \"iso\"\n");
  const ProcResult c = run_flexframe({"check", scene}, dir + "/check");
  EXPECT_EQ(c.exit_code, 2) << c.describe();
  EXPECT_NE(c.err.find("timeline[3].at"), std::string::npos) << c.describe();
}

}  // namespace
}  // namespace ff::cli::test
