// Stress fields as run outputs (core/shell/shell_stress.h through the shell simulations and the
// app): output.stresses writes every field of stress_fields() to results.h5 (names, shapes,
// descriptions, units), off by default; a stress field as output.color_field turns recording on,
// colours the frames and is in every exported VTU; replay --field reads it back by name; stress
// probes read the nodal field at their node and feed metrics, in statics and in dynamics;
// summary.json names the largest von Mises stress and where; bad field names are refused at
// their line (exit 2). Small bundled scenes, shortened: a few seconds in all.

#include <gtest/gtest.h>
#include <cmath>
#include <hdf5.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "app/frame_outputs.h"
#include "app/io/results.h"
#include "cli_support.h"
#include "core/shell/error_indicator.h"
#include "core/shell/shell_stress.h"

namespace ff::cli::test {
namespace {

const std::vector<std::string> kFixedFields = {"displacement", "strain"};
// with error bars on (the default) the error indicator comes last (core/shell/error_indicator.h)
const std::vector<std::string> kDefaultFields = {"displacement", "strain", shell::kErrorIndicatorField};

// the fields a run of an isotropic structure stores with output.stresses, in order
std::vector<std::string> expected_field_names() {
  std::vector<std::string> names = kFixedFields;
  for (const shell::StressField& f : shell::stress_fields(shell::StressLayout{})) names.push_back(f.name);
  names.push_back(shell::kErrorIndicatorField);
  return names;
}

std::vector<std::string> field_names(const RunInfo& info) {
  std::vector<std::string> names;
  for (const Quantity& q : info.fields) names.push_back(q.name);
  return names;
}

std::unique_ptr<io::ResultReader> open_results(const std::string& run_dir) {
  std::string err;
  auto r = io::ResultReader::open(run_dir + "/results.h5", &err);
  EXPECT_TRUE(r) << err;
  return r;
}

std::vector<hsize_t> dims_of(hid_t file, const std::string& name) {
  const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (d < 0) return {};
  const hid_t s = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(s);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return dims;
}

std::string string_attr(hid_t file, const std::string& obj, const char* name) {
  const hid_t a = H5Aopen_by_name(file, obj.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) return "<missing>";
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  std::string out = H5Aread(a, t, &p) < 0 ? "<unreadable>" : (p ? p : "");
  H5free_memory(p);
  H5Tclose(t);
  H5Aclose(a);
  return out;
}

// the mesh point nearest to (x, y, z)
std::size_t nearest_point(const RunInfo& info, double x, double y, double z) {
  const std::vector<double>& p = info.mesh.reference_points;
  std::size_t best = 0;
  double best_d = 1e300;
  for (std::size_t i = 0; i < info.mesh.point_count(); ++i) {
    const double d = std::hypot(p[3 * i] - x, p[3 * i + 1] - y, p[3 * i + 2] - z);
    if (d < best_d) best = i, best_d = d;
  }
  return best;
}

// 1-based number of the last line of `text` that equals `line` (what a test appended), 0 when none does
int last_line_of(const std::string& text, const std::string& line) {
  std::istringstream in(text);
  std::string l;
  int last = 0;
  for (int n = 1; std::getline(in, l); ++n)
    if (l == line) last = n;
  return last;
}

// `text` with its first `from` replaced by `to`
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

const char* kStaticProbes = R"(
[[probe]]
name = "vm_centre"
quantity = "stress"
field = "von_mises"
select = "nearest"
point = [0.5, 0.5, 0.0]

[[probe]]
name = "m11_edge"
label = "bending moment at the middle of the clamped edge x = 0"
quantity = "stress"
field = "M11"
select = "nearest"
point = [0.0, 0.5, 0.0]

[[metric]]
name = "vm_centre_final"
kind = "final"
probe = "vm_centre"

[[metric]]
name = "m11_edge_max_abs"
kind = "max_abs"
probe = "m11_edge"
)";

TEST(CliStress, StaticRunWritesEveryStressFieldOnlyWhenAsked) {
  const std::string dir = fresh_test_dir();
  const std::string on = dir + "/on", off = dir + "/off";
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", on, "--quiet", "--no-frames",
                                      "--no-plots", "--set", "output.stresses=true"},
                                     on);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto h5 = open_results(on);
  ASSERT_TRUE(h5);
  const RunInfo& info = h5->info();
  EXPECT_EQ(field_names(info), expected_field_names());
  const std::vector<shell::StressField> stresses = shell::stress_fields(shell::StressLayout{});
  const std::size_t frames = h5->frame_count(), n = info.mesh.point_count();
  ASSERT_EQ(frames, 2u);  // the reference state and the one load step
  const hid_t f = H5Fopen((on + "/results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (std::size_t k = 0; k < stresses.size(); ++k) {
    const Quantity& q = info.fields[kFixedFields.size() + k];
    EXPECT_EQ(q.label, stresses[k].description) << q.name;
    EXPECT_EQ(q.unit, "") << q.name << ": a static scene has no unit system";
    const std::string path = "/frames/fields/" + stresses[k].name;
    EXPECT_EQ(dims_of(f, path), (std::vector<hsize_t>{frames, n})) << path;
    EXPECT_EQ(string_attr(f, path, "label"), stresses[k].description) << path;
  }
  H5Fclose(f);
  // summary.json: the largest von Mises stress of the run, at its node and frame
  std::string err;
  const auto summary = read_summary(on, &err);
  ASSERT_TRUE(summary) << err;
  const Json* peak = summary->get("stresses");
  ASSERT_TRUE(peak && peak->kind == Json::Kind::object) << read_text(on + "/summary.json");
  const int vm = app::field_index(info, "von_mises");
  ASSERT_GE(vm, 0);
  double largest = -1;
  std::size_t at_node = 0, at_frame = 0;
  for (std::size_t k = 0; k < frames; ++k) {
    const Frame fr = h5->frame(k);
    for (std::size_t i = 0; i < n; ++i)
      if (fr.fields[vm][i] > largest) largest = fr.fields[vm][i], at_node = i, at_frame = k;
  }
  EXPECT_EQ(summary_number(*peak, "von_mises_max"), largest);
  EXPECT_EQ(summary_number(*peak, "node"), static_cast<double>(at_node));
  EXPECT_EQ(summary_number(*peak, "frame"), static_cast<double>(at_frame));

  // off by default: the scene's own fields only, nothing about stresses in the summary
  const ProcResult r_off =
      run_flexframe({"run", "clamped_plate_pressure", "--out", off, "--quiet", "--no-frames", "--no-plots"}, off);
  ASSERT_EQ(r_off.exit_code, 0) << r_off.describe();
  const auto h5_off = open_results(off);
  ASSERT_TRUE(h5_off);
  EXPECT_EQ(field_names(h5_off->info()), kDefaultFields);
  const auto summary_off = read_summary(off, &err);
  ASSERT_TRUE(summary_off) << err;
  EXPECT_EQ(summary_off->get("stresses"), nullptr);
}

TEST(CliStress, ColourFieldTurnsRecordingOnRendersExportsAndReplays) {
  const std::string dir = fresh_test_dir();
  const std::string run = dir + "/run";
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", run, "--quiet", "--no-plots",
                                      "--export", "vtu", "--set", "output.color_field=von_mises", "--set",
                                      "output.width=320", "--set", "output.height=240"},
                                     run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto h5 = open_results(run);
  ASSERT_TRUE(h5);
  const RunInfo& info = h5->info();
  EXPECT_EQ(field_names(info), expected_field_names()) << "naming a stress field records them all";
  const std::vector<std::string> pngs = pngs_in(run + "/frames");
  ASSERT_EQ(pngs.size(), h5->frame_count());
  const Image last = read_png(pngs.back());
  EXPECT_EQ(last.width, 320);
  EXPECT_EQ(last.height, 240);

  // every recorded field is point data of the VTU, bit for bit
  const std::size_t n = info.mesh.point_count();
  const Frame f = h5->frame(h5->frame_count() - 1);
  char stem[32];
  std::snprintf(stem, sizeof stem, "frame_%05zu", h5->frame_count() - 1);
  vtkNew<vtkXMLUnstructuredGridReader> vtu;
  vtu->SetFileName((run + "/export/" + stem + ".vtu").c_str());
  vtu->Update();
  vtkUnstructuredGrid* grid = vtu->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(n));
  for (std::size_t k = 0; k < info.fields.size(); ++k) {
    vtkDataArray* a = grid->GetPointData()->GetArray(info.fields[k].name.c_str());
    ASSERT_NE(a, nullptr) << info.fields[k].name;
    ASSERT_EQ(a->GetNumberOfTuples(), static_cast<vtkIdType>(n));
    for (std::size_t i = 0; i < n; ++i)
      ASSERT_EQ(a->GetTuple1(static_cast<vtkIdType>(i)), f.fields[k][i]) << info.fields[k].name << " point " << i;
  }
  EXPECT_NE(grid->GetPointData()->GetArray("von_mises"), nullptr);

  // replay by name from results.h5: the run's colour field and another stress field
  for (const char* field : {"von_mises", "sigma11_top"}) {
    const std::string out = dir + "/replay_" + field;
    const ProcResult p = run_flexframe({"replay", run + "/results.h5", "--out", out, "--field", field, "--size",
                                        "160x120"},
                                       out);
    ASSERT_EQ(p.exit_code, 0) << p.describe();
    EXPECT_NE(p.out.find(std::string("colour: ") + field), std::string::npos) << p.out;
    EXPECT_EQ(pngs_in(out + "/frames").size(), h5->frame_count());
  }
  // a run that did not record them lists what it has
  const std::string plain = dir + "/plain";
  ASSERT_EQ(run_flexframe({"run", "clamped_plate_pressure", "--out", plain, "--quiet", "--no-frames", "--no-plots"},
                          plain)
                .exit_code,
            0);
  const ProcResult bad =
      run_flexframe({"replay", plain + "/results.h5", "--out", dir + "/never", "--field", "von_mises"}, dir + "/bad");
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
  EXPECT_NE(bad.err.find("available: displacement, strain"), std::string::npos) << bad.err;
}

TEST(CliStress, StaticStressProbesReadTheNodalFieldAndFeedMetrics) {
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/plate.toml", run = dir + "/run";
  write_text(scene, read_text(scene_path("clamped_plate_pressure")) + kStaticProbes);
  const ProcResult r = run_flexframe({"run", scene, "--out", run, "--quiet", "--no-frames", "--no-plots"}, run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto h5 = open_results(run);
  ASSERT_TRUE(h5);
  const RunInfo& info = h5->info();
  EXPECT_EQ(field_names(info), expected_field_names()) << "a stress probe records the fields";
  const int vm = app::field_index(info, "von_mises"), m11 = app::field_index(info, "M11");
  ASSERT_GE(vm, 0);
  ASSERT_GE(m11, 0);
  const std::size_t centre = nearest_point(info, 0.5, 0.5, 0.0), edge = nearest_point(info, 0.0, 0.5, 0.0);
  const std::vector<double> vm_series = h5->probe_series("vm_centre"), m11_series = h5->probe_series("m11_edge");
  ASSERT_EQ(vm_series.size(), h5->frame_count());
  ASSERT_EQ(m11_series.size(), h5->frame_count());
  for (std::size_t k = 0; k < h5->frame_count(); ++k) {
    const Frame f = h5->frame(k);
    EXPECT_EQ(vm_series[k], f.fields[vm][centre]) << "frame " << k;
    EXPECT_EQ(m11_series[k], f.fields[m11][edge]) << "frame " << k;
  }
  std::string err;
  const auto summary = read_summary(run, &err);
  ASSERT_TRUE(summary) << err;
  expect_summary_shape(*summary);
  const Json* metrics = summary->get("metrics");
  ASSERT_TRUE(metrics);
  double largest = 0;
  for (double x : m11_series) largest = std::max(largest, std::fabs(x));
  EXPECT_EQ(summary_number(*metrics, "vm_centre_final"), vm_series.back());
  EXPECT_EQ(summary_number(*metrics, "m11_edge_max_abs"), largest);
}

TEST(CliStress, DynamicRunRecordsStressesInPascalAndProbesThem) {
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/strip.toml", run = dir + "/run";
  write_text(scene, read_text(scene_path("cantilever_step_load")) + R"(
[[probe]]
name = "vm_root"
quantity = "stress"
field = "von_mises"
select = "nearest"
point = [0.0, 0.05, 0.0]

[[metric]]
name = "vm_root_peak"
kind = "max"
probe = "vm_root"
)");
  // 20 steps of 1 ms, every one a frame, so the frames hold every value the metric saw
  const ProcResult r = run_flexframe({"run", scene, "--out", run, "--quiet", "--no-frames", "--no-plots", "--set",
                                      "solver.end=0.02", "--set", "solver.output_every=1", "--set",
                                      "output.stresses=true"},
                                     run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto h5 = open_results(run);
  ASSERT_TRUE(h5);
  const RunInfo& info = h5->info();
  EXPECT_EQ(field_names(info), expected_field_names());
  const auto unit_of = [&](const std::string& name) {
    const int k = app::field_index(info, name);
    return k >= 0 ? info.fields[k].unit : "<no field " + name + ">";
  };
  EXPECT_EQ(unit_of("von_mises"), "Pa");
  EXPECT_EQ(unit_of("sigma12_mid"), "Pa");
  EXPECT_EQ(unit_of("principal2_top"), "Pa");
  EXPECT_EQ(unit_of("N11"), "N/m");
  EXPECT_EQ(unit_of("Q2"), "N/m");
  EXPECT_EQ(unit_of("M12"), "N");
  for (const Quantity& p : info.probes)
    if (p.name == "vm_root") { EXPECT_EQ(p.unit, "Pa"); }
  ASSERT_EQ(h5->frame_count(), 21u);
  const int vm = app::field_index(info, "von_mises");
  const std::size_t root = nearest_point(info, 0.0, 0.05, 0.0);
  const std::vector<double> series = h5->probe_series("vm_root");
  ASSERT_EQ(series.size(), h5->frame_count());
  double peak = series.front();
  for (std::size_t k = 0; k < series.size(); ++k) {
    EXPECT_EQ(series[k], h5->frame(k).fields[vm][root]) << "frame " << k;
    peak = std::max(peak, series[k]);
  }
  std::string err;
  const auto summary = read_summary(run, &err);
  ASSERT_TRUE(summary) << err;
  EXPECT_EQ(summary_number(*summary->get("metrics"), "vm_root_peak"), peak);
  const Json* stresses = summary->get("stresses");
  ASSERT_TRUE(stresses);
  EXPECT_EQ(summary_string(*stresses, "unit"), "Pa");
}

TEST(CliStress, UnknownStressNamesAndMisplacedKeysAreRefusedAtTheirLine) {
  const std::string dir = fresh_test_dir();
  const std::string plate = read_text(scene_path("clamped_plate_pressure"));
  const std::string strip = read_text(scene_path("cantilever_step_load"));
  struct Case {
    std::string name, text, line, key, message;
  };
  const std::string probe_head = "\n[[probe]]\nname = \"extra\"\nselect = \"nearest\"\npoint = [0.5, 0.5, 0.0]\n";
  const std::vector<Case> cases = {
      // the [output] table ends the plate's scene: a key appended lands in it
      {"colour_typo", plate + "color_field = \"von_mises_tpo\"\n", "color_field = \"von_mises_tpo\"",
       "key 'output.color_field'", "its fields: displacement, strain, von_mises, "},
      {"colour_ply_of_isotropic", plate + "color_field = \"ply1_sigma1\"\n", "color_field = \"ply1_sigma1\"",
       "key 'output.color_field'", "follow the structure's layup"},
      {"colour_dynamic", replaced(strip, "color_field = \"displacement\"", "color_field = \"Mises\""),
       "color_field = \"Mises\"", "key 'output.color_field'", "not a field of this run"},
      {"probe_field_typo", plate + probe_head + "quantity = \"stress\"\nfield = \"vonmises\"\n", "field = \"vonmises\"",
       "key 'probe[1].field'", "its fields: von_mises, "},
      {"probe_field_without_stress", plate + probe_head + "direction = [0.0, 0.0, 1.0]\nfield = \"von_mises\"\n",
       "field = \"von_mises\"", "key 'probe[1].field'", "belongs to quantity = \"stress\""},
      {"stress_probe_with_direction",
       plate + probe_head + "quantity = \"stress\"\nfield = \"N11\"\ndirection = [0.0, 0.0, 1.0]\n",
       "direction = [0.0, 0.0, 1.0]", "key 'probe[1].direction'", "along no direction"},
      {"stress_probe_without_field", plate + probe_head + "quantity = \"stress\"\n", "quantity = \"stress\"",
       "key 'probe[1].quantity'", "needs probe.field"},
      {"displacement_probe_without_direction", plate + probe_head, "[[probe]]", "key 'probe[1].direction'",
       "needs probe.direction"},
      {"dynamic_probe_field_typo", strip + probe_head + "quantity = \"stress\"\nfield = \"ply1_sigma1\"\n",
       "field = \"ply1_sigma1\"", "key 'probe[1].field'", "follow the structure's layup"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string scene = dir + "/" + c.name + ".toml";
    write_text(scene, c.text);
    const int line = last_line_of(c.text, c.line);
    ASSERT_GT(line, 0);
    // check refuses what run would refuse at start-up: run is asked once
    for (const char* verb : {"check", "run"}) {
      if (std::string(verb) == "run" && &c != &cases.front() && &c != &cases.back()) continue;
      const std::vector<std::string> args = std::string(verb) == "check"
                                                ? std::vector<std::string>{"check", scene}
                                                : std::vector<std::string>{"run", scene, "--out", dir + "/never", "--quiet"};
      const ProcResult r = run_flexframe(args, dir + "/" + c.name + "_" + verb);
      EXPECT_EQ(r.exit_code, 2) << verb << "\n" << r.describe();
      EXPECT_NE(r.err.find(scene + ":" + std::to_string(line) + ":"), std::string::npos) << verb << "\n" << r.err;
      EXPECT_NE(r.err.find(c.key), std::string::npos) << verb << "\n" << r.err;
      EXPECT_NE(r.err.find(c.message), std::string::npos) << verb << "\n" << r.err;
    }
  }
  EXPECT_FALSE(fs::exists(dir + "/never/results.h5")) << "a refused scene runs nothing";
  // the hub-beam has no shell stresses: its output table does not take the key
  const ProcResult hub = run_flexframe({"check", "hub_beam_fem_tau1", "--set", "output.stresses=true"}, dir + "/hub");
  EXPECT_EQ(hub.exit_code, 2) << hub.describe();
  EXPECT_NE(hub.err.find("output.stresses"), std::string::npos) << hub.err;
}

}  // namespace
}  // namespace ff::cli::test

namespace ff::cli::test {
namespace {
// A laminated roof, shortened: its stored fields are the isotropic ones, then tsai_wu and the ply
// fields of its three plies (stress_fields of a 3-ply layout with strengths, in that order); a ply
// field colours the frames and replays; a ply the layup lacks is refused at its line.
TEST(CliStress, LaminatedRoofRecordsItsPliesAndTheirFailureIndex) {
  const std::string dir = fresh_test_dir();
  const std::string run = dir + "/run";
  const std::vector<std::string> strengths = {"material[0].strength_xt=60.0", "material[0].strength_xc=120.0",
                                              "material[0].strength_yt=20.0", "material[0].strength_yc=60.0",
                                              "material[0].strength_s12=30.0"};
  std::vector<std::string> args = {"run", "hinged_roof_h127_0_90_0", "--out", run, "--quiet", "--no-plots",
                                   "--set", "solver.end=0.2", "--set", "output.frame_every=6", "--set",
                                   "output.color_field=ply2_sigma1", "--set", "output.width=320", "--set",
                                   "output.height=240"};
  for (const std::string& s : strengths) args.insert(args.end(), {"--set", s});
  const ProcResult r = run_flexframe(args, run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto h5 = open_results(run);
  ASSERT_TRUE(h5);
  std::vector<std::string> expected = kFixedFields;
  for (const shell::StressField& f : shell::stress_fields(shell::StressLayout{3, true})) expected.push_back(f.name);
  expected.push_back(shell::kErrorIndicatorField);
  EXPECT_EQ(field_names(h5->info()), expected);
  EXPECT_GE(pngs_in(run + "/frames").size(), 2u) << "every 6th step drawn (results.h5 keeps every step)";
  // the middle ply runs around the arc (90 degrees from the axis): under the load its fibres carry
  // stress, and every ply's failure index is finite and not negative at the loaded crown
  const Frame last = h5->frame(h5->frame_count() - 1);
  const RunInfo& info = h5->info();
  const std::size_t crown = nearest_point(info, 0.0, 0.0, 0.0);
  for (std::size_t k = 0; k < info.fields.size(); ++k) {
    const std::string& name = info.fields[k].name;
    if (name == "ply2_sigma1") { EXPECT_NE(last.fields[k][crown], 0.0); }
    if (name.find("tsai_wu") != std::string::npos) { EXPECT_TRUE(std::isfinite(last.fields[k][crown])) << name; }
  }
  const std::string out = dir + "/replay";
  const ProcResult p =
      run_flexframe({"replay", run + "/results.h5", "--out", out, "--field", "ply3_tsai_wu", "--size", "160x120"}, out);
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  const ProcResult bad = run_flexframe({"check", "hinged_roof_h127_0_90_0", "--set", "output.color_field=ply4_sigma1"},
                                       dir + "/bad");
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
  EXPECT_NE(bad.err.find("output.color_field"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("ply3_sigma1"), std::string::npos) << bad.err << " (the fields it has are listed)";
}
}  // namespace
}  // namespace ff::cli::test
