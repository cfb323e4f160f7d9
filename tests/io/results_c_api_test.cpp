// results.h5 opens with nothing but the HDF5 C API and has the layout results_layout.md
// promises: names, shapes, types and attributes a Python/h5py user relies on.

#include <gtest/gtest.h>
#include <hdf5.h>

#include "app/io/results.h"
#include "results_test_data.h"

namespace ff::io {
namespace {

using test::make_frame;
using test::make_info;
using test::out_path;

std::vector<hsize_t> dims_of(hid_t file, const char* name) {
  hid_t d = H5Dopen2(file, name, H5P_DEFAULT);
  if (d < 0) return {};
  hid_t s = H5Dget_space(d);
  int rank = H5Sget_simple_extent_ndims(s);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return dims;
}

std::string string_attr(hid_t file, const char* obj, const char* name) {
  hid_t a = H5Aopen_by_name(file, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) return "<missing>";
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  std::string out = H5Aread(a, t, &p) < 0 ? "<unreadable>" : (p ? p : "");
  H5free_memory(p);
  H5Tclose(t);
  H5Aclose(a);
  return out;
}

double double_attr(hid_t file, const char* obj, const char* name) {
  double v = -1.0;
  hid_t a = H5Aopen_by_name(file, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
  }
  return v;
}

TEST(ResultStoreCApi, LayoutAsDocumented) {
  const std::string path = out_path("c_api.h5");
  const RunInfo info = make_info(60, 3, 2);
  std::string error;
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    for (int i = 0; i < 120; ++i) { ASSERT_TRUE(w->append(make_frame(info, i), &error)); }
    w->set_attribute("git_hash", "abc123");
    RunOutcome o;
    o.status = RunStatus::diverged;
    o.reason = "step cut-backs exhausted";
    ASSERT_TRUE(w->finish(o, {{"peak_angle_deg", 12.5}}, &error)) << error;
  }

  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(string_attr(f, "/", "format"), "flexframe-results");
  EXPECT_EQ(double_attr(f, "/", "format_version"), 1.0);
  EXPECT_EQ(string_attr(f, "/run", "scene_name"), "strip_test");
  EXPECT_EQ(string_attr(f, "/run", "time_unit"), "s");
  EXPECT_EQ(string_attr(f, "/run/settings", "integrator"), "lie_generalized_alpha");
  EXPECT_EQ(string_attr(f, "/outcome", "status"), "diverged");
  EXPECT_EQ(string_attr(f, "/outcome", "reason"), "step cut-backs exhausted");
  EXPECT_EQ(double_attr(f, "/outcome", "finished"), 1.0);
  EXPECT_EQ(double_attr(f, "/metrics", "peak_angle_deg"), 12.5);
  EXPECT_EQ(string_attr(f, "/attributes", "git_hash"), "abc123");
  EXPECT_EQ(double_attr(f, "/frames", "frames_written"), 120.0);
  EXPECT_EQ(string_attr(f, "/frames/probes/probe_0", "unit"), "deg");
  EXPECT_EQ(string_attr(f, "/frames/probes/probe_0", "label"), "probe number 0");
  EXPECT_EQ(string_attr(f, "/frames/time", "unit"), "s");

  using D = std::vector<hsize_t>;
  EXPECT_EQ(dims_of(f, "/mesh/reference_points"), (D{60, 3}));
  EXPECT_EQ(dims_of(f, "/mesh/lines"), (D{29, 2}));
  EXPECT_EQ(dims_of(f, "/mesh/triangles"), (D{29, 3}));
  EXPECT_EQ(dims_of(f, "/mesh/quads"), (D{29, 4}));
  EXPECT_EQ(dims_of(f, "/run/scene_text"), (D{}));  // scalar string
  EXPECT_EQ(dims_of(f, "/frames/time"), (D{120}));
  EXPECT_EQ(dims_of(f, "/frames/step"), (D{120}));
  EXPECT_EQ(dims_of(f, "/frames/load_factor"), (D{120}));
  EXPECT_EQ(dims_of(f, "/frames/points"), (D{120, 60, 3}));
  EXPECT_EQ(dims_of(f, "/frames/base_points"), (D{120, 60, 3}));
  EXPECT_EQ(dims_of(f, "/frames/probes/probe_2"), (D{120}));
  EXPECT_EQ(dims_of(f, "/frames/fields/field_1"), (D{120, 60}));
  for (const char* s : {"dt", "iterations", "jacobian_updates", "residual_norm", "increment_norm",
                        "converged"}) {
    EXPECT_EQ(dims_of(f, ("/frames/stats/" + std::string(s)).c_str()), (D{120})) << s;
  }

  // points of frame 17 read with a hyperslab, as a C or Fortran user would
  hid_t d = H5Dopen2(f, "/frames/points", H5P_DEFAULT);
  hid_t fs = H5Dget_space(d);
  hsize_t start[3] = {17, 0, 0}, count[3] = {1, 60, 3};
  H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, nullptr, count, nullptr);
  hid_t ms = H5Screate_simple(3, count, nullptr);
  std::vector<double> p(180);
  EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, p.data()), 0);
  EXPECT_TRUE(test::bitwise_equal(p, make_frame(info, 17).points));
  H5Sclose(ms);
  H5Sclose(fs);
  H5Dclose(d);

  // converged is an enum {FALSE, TRUE} over int8 (h5py: numpy bool)
  d = H5Dopen2(f, "/frames/stats/converged", H5P_DEFAULT);
  hid_t t = H5Dget_type(d);
  EXPECT_EQ(H5Tget_class(t), H5T_ENUM);
  EXPECT_EQ(H5Tget_size(t), 1u);
  char member[8] = {0};
  std::int8_t one = 1;
  EXPECT_GE(H5Tenum_nameof(t, &one, member, sizeof member), 0);
  EXPECT_STREQ(member, "TRUE");
  H5Tclose(t);
  H5Dclose(d);

  // the scene text is a scalar variable-length UTF-8 string
  d = H5Dopen2(f, "/run/scene_text", H5P_DEFAULT);
  t = H5Dget_type(d);
  EXPECT_TRUE(H5Tis_variable_str(t) > 0);
  EXPECT_EQ(H5Tget_cset(t), H5T_CSET_UTF8);
  char* text = nullptr;
  EXPECT_GE(H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text), 0);
  EXPECT_EQ(std::string(text ? text : ""), info.scene_text);
  H5free_memory(text);
  H5Tclose(t);
  H5Dclose(d);
  EXPECT_GE(H5Fclose(f), 0);
}

}  // namespace
}  // namespace ff::io
