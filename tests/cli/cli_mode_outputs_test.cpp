// The outputs of an eigen-analysis (issue 36 item 4; docs/guide/mode_outputs.md), driven through
// the production path (run_loaded_scene: the run asks Simulation::modes() after the run) by a
// test model whose modes are known in closed form: a simply supported rectangular plate a x b,
// whose mode (m, n) is w = sin(mπx/a) sin(nπy/b) at f = (π/2)(m²/a² + n²/b²) sqrt(D/(ρh))
// (Leissa, Vibration of Plates, NASA SP-160, 1969). Checked: results.h5 /modes round
// trip, the summary.json table, the animations (24 frames per mode, phases that differ, the
// drawn shape), the spectrum plot, export/modes.vtu, the MP4s, and `flexframe replay --mode`
// with its bad input.

#include <gtest/gtest.h>
#include <hdf5.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <numbers>

#include "app/io/movie_writer.h"
#include "app/io/results.h"
#include "app/mode_outputs.h"
#include "app/run_session.h"
#include "cli_support.h"
#include "tests/support/plate_modes.h"

namespace ff::cli::test {
namespace {

using namespace ff::test;

app::RunResult run_plate(const std::string& out, bool with_modes = true, bool movie = false,
                         const std::string& export_formats = "", int animate_modes = -1,
                         const std::atomic<bool>* stop_flag = nullptr) {
  scene::LoadedScene scene;
  scene.name = "ss_plate_modes";
  scene.path = "(test model)";
  scene.simulation = std::make_unique<PlateModesSimulation>(with_modes);
  scene.output.width = 480;
  scene.output.height = 360;
  app::RunOptions opt;
  opt.out_dir = out;
  opt.progress = false;
  opt.movie = movie;
  opt.export_formats = export_formats;
  opt.animate_modes = animate_modes;
  const std::atomic<bool> stop{false};
  return app::run_loaded_scene(opt, std::move(scene), stop_flag ? *stop_flag : stop);
}

std::size_t differing_pixels(const ff::render::test::Image& a, const render::test::Image& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < std::min(a.rgb.size(), b.rgb.size()); ++i) n += a.rgb[i] != b.rgb[i];
  return n;
}

TEST(ModeOutputs, ResultsFileKeepsTheModesBitForBit) {
  const std::string dir = fresh_test_dir();
  const RunInfo info = plate_info();
  ModeSet set = plate_modes(info);
  set.modes[1].rigid_body = true;  // the flag travels too
  set.modes[1].value = 0.0;
  std::string err;
  {
    auto w = io::ResultWriter::create(dir + "/results.h5", info, &err);
    ASSERT_TRUE(w) << err;
    Frame f;
    f.points = f.base_points = info.mesh.reference_points;
    f.fields = {std::vector<double>(info.mesh.point_count(), 0.0)};
    ASSERT_TRUE(w->append(f, &err)) << err;
    ASSERT_TRUE(w->write_modes(set, &err)) << err;
    EXPECT_FALSE(w->write_modes(set, &err)) << "the modes are written once";
    ASSERT_TRUE(w->finish({}, {}, &err)) << err;
  }
  const auto r = io::ResultReader::open(dir + "/results.h5", &err);
  ASSERT_TRUE(r) << err;
  const ModeSet* back = r->modes();
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->analysis, "modal");
  EXPECT_EQ(back->about, "reference state");
  EXPECT_EQ(back->value_name, "frequency");
  EXPECT_EQ(back->value_unit, "Hz");
  EXPECT_EQ(back->value_label, "natural frequency");
  ASSERT_EQ(back->modes.size(), set.modes.size());
  for (std::size_t k = 0; k < set.modes.size(); ++k) {
    EXPECT_EQ(back->modes[k].number, set.modes[k].number);
    EXPECT_EQ(back->modes[k].value, set.modes[k].value);
    EXPECT_EQ(back->modes[k].eigenvalue, set.modes[k].eigenvalue);
    EXPECT_EQ(back->modes[k].rigid_body, set.modes[k].rigid_body);
    EXPECT_EQ(back->modes[k].displacement, set.modes[k].displacement);
  }
  EXPECT_EQ(r->verify(), "");

  // a displacement that does not fit the mesh is refused and nothing is stored
  {
    auto w = io::ResultWriter::create(dir + "/short.h5", info, &err);
    ASSERT_TRUE(w) << err;
    ModeSet bad = set;
    bad.modes[2].displacement.pop_back();
    EXPECT_FALSE(w->write_modes(bad, &err));
    EXPECT_NE(err.find("mode 3 has"), std::string::npos) << err;
    ASSERT_TRUE(w->finish({}, {}, &err)) << err;
  }
  const auto s = io::ResultReader::open(dir + "/short.h5", &err);
  ASSERT_TRUE(s) << err;
  EXPECT_EQ(s->modes(), nullptr) << "a file without /modes has no modes";
}

TEST(ModeOutputs, AnimationIsTheBaseStatePlusAScaledSineOfTheMode) {
  const RunInfo info = plate_info();
  const ModeSet set = plate_modes(info);
  Frame base;
  base.points = info.mesh.reference_points;
  const app::ModeAnimation a = app::mode_animation(info, base, set, set.modes[0], 24, 0.1);
  const double size = std::hypot(kA, kB);
  EXPECT_DOUBLE_EQ(a.amplitude, 0.1 * size);
  ASSERT_EQ(a.frames.size(), 24u);
  // the centre node (mode (1, 1): its largest value) at a quarter period is a above the plate
  const std::size_t centre = (kNy / 2) * (kNx + 1) + kNx / 2;
  EXPECT_NEAR(a.frames[6].points[3 * centre + 2], a.amplitude, 1e-12);
  EXPECT_NEAR(a.frames[18].points[3 * centre + 2], -a.amplitude, 1e-12);
  EXPECT_EQ(a.frames[0].points, base.points);
  EXPECT_EQ(a.frames[6].base_points, base.points) << "the ghost is the state the mode is about";
  ASSERT_EQ(a.info.fields.size(), 1u);
  EXPECT_DOUBLE_EQ(a.frames[6].fields[0][centre], 1.0);
  EXPECT_DOUBLE_EQ(a.frames[6].fields[0][0], 0.0) << "a supported corner does not move";
  EXPECT_NE(a.title.find("mode 1 of 6"), std::string::npos) << a.title;
  EXPECT_NE(a.title.find("Hz"), std::string::npos) << a.title;
  EXPECT_NE(a.caption.find("arbitrary"), std::string::npos) << a.caption;
  EXPECT_NE(a.caption.find("10 % of the model's size"), std::string::npos) << a.caption;

  ModeSet bad = set;
  bad.modes[0].displacement[3 * centre + 2] = std::nan("");
  try {
    app::mode_animation(info, base, bad, bad.modes[0]);
    ADD_FAILURE() << "a NaN displacement was animated";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mode 1 has a non-finite displacement at point " + std::to_string(centre)),
              std::string::npos)
        << e.what();
  }
}

// a buckling analysis' modes are named by their load multipliers, not as frequencies
TEST(ModeOutputs, BucklingModesAreNamedByTheirLoadMultipliers) {
  const RunInfo info = plate_info();
  ModeSet set = plate_modes(info);
  set.analysis = "buckling";
  set.value_name = "load_multiplier";
  set.value_unit = "";
  set.value_label = "load multiplier";
  set.about = "state preloaded to lambda = 1";
  set.modes[0].value = 3.52;
  EXPECT_EQ(app::mode_value_text(set, set.modes[0]), "load multiplier 3.52");
  Frame base;
  base.points = info.mesh.reference_points;
  const app::ModeAnimation a = app::mode_animation(info, base, set, set.modes[0]);
  EXPECT_NE(a.title.find("mode 1 of 6, load multiplier 3.52"), std::string::npos) << a.title;
  EXPECT_EQ(a.title.find("Hz"), std::string::npos) << a.title;
  EXPECT_NE(a.caption.find("about the state preloaded to lambda = 1"), std::string::npos) << a.caption;
  const auto json = app::modes_json(set);
  EXPECT_EQ(json["analysis"], "buckling");
  EXPECT_EQ(json["value_name"], "load_multiplier");
  EXPECT_EQ(json["modes"][0]["value"], 3.52);
}

TEST(ModeOutputs, RunWritesTheTableTheAnimationsAndTheSpectrum) {
  const std::string out = fresh_test_dir() + "/run";
  const app::RunResult r = run_plate(out);
  ASSERT_EQ(r.outcome.status, RunStatus::completed) << r.outcome.reason;
  EXPECT_EQ(r.modes, kModeCount);
  EXPECT_EQ(r.modes_animated, kModeCount);

  // summary.json: the table as the analysis gave it
  std::string err;
  const auto summary = read_summary(out, &err);
  ASSERT_TRUE(summary) << err;
  const Json* modes = summary->get("modes");
  ASSERT_NE(modes, nullptr);
  EXPECT_EQ(modes->get("analysis")->string, "modal");
  EXPECT_EQ(modes->get("about")->string, "reference state");
  EXPECT_EQ(modes->get("value_name")->string, "frequency");
  EXPECT_EQ(modes->get("value_unit")->string, "Hz");
  const Json* rows = modes->get("modes");
  ASSERT_NE(rows, nullptr);
  std::vector<std::pair<int, int>> mn;
  const ModeSet expected = plate_modes(plate_info(), &mn);
  ASSERT_EQ(rows->array.size(), expected.modes.size());
  for (std::size_t k = 0; k < rows->array.size(); ++k) {
    const Json& row = rows->array[k];
    EXPECT_EQ(row.get("number")->number, expected.modes[k].number);
    EXPECT_NEAR(row.get("value")->number, expected.modes[k].value, 1e-12 * expected.modes[k].value);
    EXPECT_NEAR(row.get("eigenvalue")->number, expected.modes[k].eigenvalue, 1e-12 * expected.modes[k].eigenvalue);
    EXPECT_EQ(row.get("rigid_body")->kind, Json::Kind::boolean);
    EXPECT_FALSE(row.get("rigid_body")->boolean);
  }
  // results.h5 holds the same modes
  const auto reader = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(reader) << err;
  ASSERT_NE(reader->modes(), nullptr);
  EXPECT_EQ(reader->modes()->modes.size(), expected.modes.size());
  EXPECT_EQ(reader->modes()->modes[3].displacement, expected.modes[3].displacement);
  {  // the layout results_layout.md documents, as any HDF5 reader sees it
    const hid_t file = H5Fopen((out + "/results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    const auto dims_of = [&](const char* path) {
      const hid_t d = H5Dopen2(file, path, H5P_DEFAULT);
      const hid_t space = H5Dget_space(d);
      std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(space))));
      H5Sget_simple_extent_dims(space, dims.data(), nullptr);
      H5Sclose(space);
      H5Dclose(d);
      return dims;
    };
    const hsize_t n = plate_info().mesh.point_count();
    EXPECT_EQ(dims_of("/modes/displacement"), (std::vector<hsize_t>{kModeCount, n, 3}));
    EXPECT_EQ(dims_of("/modes/value"), (std::vector<hsize_t>{kModeCount}));
    const hid_t rigid = H5Dopen2(file, "/modes/rigid_body", H5P_DEFAULT);
    const hid_t type = H5Dget_type(rigid);
    EXPECT_EQ(H5Tget_class(type), H5T_ENUM) << "a bool as the frames' converged flag";
    H5Tclose(type);
    H5Dclose(rigid);
    H5Fclose(file);
  }

  // one looping animation per mode, 24 frames, whose phases differ
  for (int m = 1; m <= kModeCount; ++m) {
    char dir[64];
    std::snprintf(dir, sizeof dir, "/frames/mode_%02d", m);
    const auto pngs = pngs_in(out + dir);
    ASSERT_EQ(pngs.size(), 24u) << dir;
    const auto rest = ff::render::test::read_png(pngs[0]), up = ff::render::test::read_png(pngs[6]),
               down = ff::render::test::read_png(pngs[18]);
    ASSERT_EQ(up.width, 480);
    EXPECT_GT(differing_pixels(rest, up), 2000u) << dir << ": a quarter period moves the plate";
    EXPECT_GT(differing_pixels(up, down), 2000u) << dir << ": up and down are different pictures";
  }
  EXPECT_TRUE(fs::is_regular_file(out + "/plots/spectrum.png"));
  const Json* outputs = summary->get("outputs");
  ASSERT_NE(outputs, nullptr);
  const Json* mode_outputs = outputs->get("modes");
  ASSERT_NE(mode_outputs, nullptr);
  EXPECT_EQ(mode_outputs->get("animated")->number, kModeCount);
  EXPECT_EQ(mode_outputs->get("frames")->number, 24 * kModeCount);
  EXPECT_EQ(mode_outputs->get("spectrum_plot")->string, "plots/spectrum.png");
  // every file is the run's: in the folder's manifest (a later run may delete them)
  const std::string manifest = read_text(out + "/.flexframe-files");
  EXPECT_NE(manifest.find("frames/mode_03/frame_00023.png"), std::string::npos);
  EXPECT_NE(manifest.find("plots/spectrum.png"), std::string::npos);
}

// --animate-modes N animates the first N modes; the table and the spectrum keep every mode
TEST(ModeOutputs, AnimateModesCapsTheAnimations) {
  const std::string dir = fresh_test_dir();
  const app::RunResult two = run_plate(dir + "/two", true, false, "", 2);
  EXPECT_EQ(two.modes, kModeCount);
  EXPECT_EQ(two.modes_animated, 2);
  EXPECT_EQ(pngs_in(dir + "/two/frames/mode_02").size(), 24u);
  EXPECT_FALSE(fs::exists(dir + "/two/frames/mode_03"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/two/plots/spectrum.png"));
  std::string err;
  const auto summary = read_summary(dir + "/two", &err);
  ASSERT_TRUE(summary) << err;
  EXPECT_EQ(summary->get("modes")->get("modes")->array.size(), static_cast<std::size_t>(kModeCount));
  const app::RunResult none = run_plate(dir + "/none", true, false, "", 0);
  EXPECT_EQ(none.modes_animated, 0);
  EXPECT_FALSE(fs::exists(dir + "/none/frames/mode_01"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/none/plots/spectrum.png"));
}

// a run of the same folder without modes leaves none of the earlier run's mode pictures behind
TEST(ModeOutputs, ALaterRunRemovesTheEarlierModePictures) {
  const std::string out = fresh_test_dir() + "/run";
  ASSERT_EQ(run_plate(out).modes_animated, kModeCount);
  ASSERT_TRUE(fs::is_directory(out + "/frames/mode_01"));
  const app::RunResult again = run_plate(out, false);
  EXPECT_EQ(again.modes, -1);
  EXPECT_FALSE(fs::exists(out + "/frames/mode_01"));
  EXPECT_FALSE(fs::exists(out + "/plots/spectrum.png"));
  std::string err;
  const auto summary = read_summary(out, &err);
  ASSERT_TRUE(summary) << err;
  EXPECT_EQ(summary->get("modes"), nullptr) << "no table for a run that computes no modes";
}

TEST(ModeOutputs, VtuCarriesEveryModeAsAPointVector) {
  const std::string out = fresh_test_dir() + "/run";
  ASSERT_EQ(run_plate(out, true, false, "vtu").outcome.status, RunStatus::completed);
  vtkNew<vtkXMLUnstructuredGridReader> vtu;
  vtu->SetFileName((out + "/export/modes.vtu").c_str());
  vtu->Update();
  vtkUnstructuredGrid* grid = vtu->GetOutput();
  const ModeSet expected = plate_modes(plate_info());
  const std::size_t n = plate_info().mesh.point_count();
  ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(n));
  for (const Mode& m : expected.modes) {
    vtkDataArray* a = grid->GetPointData()->GetArray(("mode_" + std::to_string(m.number)).c_str());
    ASSERT_NE(a, nullptr) << "mode_" << m.number;
    ASSERT_EQ(a->GetNumberOfComponents(), 3);
    double diff = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        diff = std::max(diff, std::fabs(a->GetComponent(static_cast<vtkIdType>(i), c) - m.displacement[3 * i + c]));
    EXPECT_EQ(diff, 0.0) << "mode_" << m.number;
  }
  vtkDataArray* f = grid->GetFieldData()->GetArray("mode_frequency");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(f->GetNumberOfTuples(), kModeCount);
  EXPECT_EQ(f->GetTuple1(2), expected.modes[2].value);
}

TEST(ModeOutputs, MovieLoopsEachModesPeriod) {
  if (!io::movie_support().empty()) GTEST_SKIP() << io::movie_support();
  const std::string out = fresh_test_dir() + "/run";
  const app::RunResult r = run_plate(out, true, true);
  ASSERT_EQ(r.outcome.status, RunStatus::completed) << r.outcome.reason;
  for (int m = 1; m <= kModeCount; ++m) {
    char name[64];
    std::snprintf(name, sizeof name, "/modes/mode_%02d.mp4", m);
    io::MovieInfo movie;
    std::string err;
    ASSERT_TRUE(io::probe_movie(out + name, &movie, &err)) << name << ": " << err;
    EXPECT_EQ(movie.frames, 24 * app::kModeMovieCycles) << name;
    EXPECT_EQ(movie.width, 480);
  }
}

TEST(ModeOutputs, ReplayAnimatesTheChosenModesOfAStoredRun) {
  const std::string dir = fresh_test_dir();
  ASSERT_EQ(run_plate(dir + "/run").outcome.status, RunStatus::completed);
  const ProcResult p =
      run_flexframe({"replay", dir + "/run", "--out", dir + "/replay", "--mode", "2,5", "--size", "400x300"}, dir + "/replay");
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  EXPECT_EQ(pngs_in(dir + "/replay/frames/mode_02").size(), 24u);
  EXPECT_EQ(pngs_in(dir + "/replay/frames/mode_05").size(), 24u);
  EXPECT_FALSE(fs::exists(dir + "/replay/frames/mode_01")) << "only the modes asked for";
  EXPECT_TRUE(fs::is_regular_file(dir + "/replay/plots/spectrum.png"));
  EXPECT_NE(p.out.find("modes: 6 stored"), std::string::npos) << p.out;
  // the stored run's mode 2 and its replay are the same picture at the same size
  const auto replayed = ff::render::test::read_png(pngs_in(dir + "/replay/frames/mode_02")[6]);
  EXPECT_EQ(replayed.width, 400);
  EXPECT_EQ(replayed.height, 300);

  // bad input, before anything is written: a mode the file does not have, modes of a run without any
  const ProcResult missing = run_flexframe({"replay", dir + "/run", "--out", dir + "/bad", "--mode", "9"}, dir + "/bad");
  EXPECT_EQ(missing.exit_code, 2) << missing.describe();
  EXPECT_NE(missing.err.find("--mode 9: no such mode; the modal analysis stored modes 1, 2, 3, 4, 5, 6"), std::string::npos)
      << missing.err;
  EXPECT_FALSE(fs::exists(dir + "/bad"));
  const ProcResult no_frames =
      run_flexframe({"replay", dir + "/run", "--out", dir + "/bad3", "--mode", "2", "--no-frames"}, dir + "/bad3");
  EXPECT_EQ(no_frames.exit_code, 2) << no_frames.describe();
  EXPECT_NE(no_frames.err.find("--mode animates modes as PNG frames"), std::string::npos) << no_frames.err;
  ASSERT_EQ(run_plate(dir + "/plain", false).modes, -1);
  const ProcResult none = run_flexframe({"replay", dir + "/plain", "--out", dir + "/bad2", "--mode", "1"}, dir + "/bad2");
  EXPECT_EQ(none.exit_code, 2) << none.describe();
  EXPECT_NE(none.err.find("stores no modes"), std::string::npos) << none.err;
}

TEST(ModeOutputs, SpectrumMarksRigidBodyModes) {
  const std::string dir = fresh_test_dir();
  const RunInfo info = plate_info();
  ModeSet set = plate_modes(info);
  // a free plate's three rigid-body modes ahead of the elastic ones (the drawing, not the physics, is tested)
  for (int k = 0; k < 3; ++k) {
    Mode rigid;
    rigid.rigid_body = true;
    rigid.displacement.assign(3 * info.mesh.point_count(), 0.0);
    for (std::size_t i = 0; i < info.mesh.point_count(); ++i)
      rigid.displacement[3 * i + 2] = k == 0 ? 1.0 : k == 1 ? info.mesh.reference_points[3 * i] / kA - 0.5
                                                            : info.mesh.reference_points[3 * i + 1] / kB - 0.5;
    set.modes.insert(set.modes.begin() + k, rigid);
  }
  for (std::size_t k = 0; k < set.modes.size(); ++k) set.modes[k].number = static_cast<int>(k + 1);
  app::OutputFolder folder(dir, "test");
  app::ModeOutputOptions opt;
  opt.frames = false;
  const std::atomic<bool> stop{false};
  Frame base;
  base.points = info.mesh.reference_points;
  const app::ModeOutputReport r = app::write_mode_outputs(folder, info, base, set, opt, nullptr, stop);
  ASSERT_EQ(r.error, "");
  ASSERT_EQ(r.plot, "plots/spectrum.png");
  const auto img = ff::render::test::read_png(dir + "/plots/spectrum.png");
  EXPECT_GT(img.width, 0);
  EXPECT_EQ(app::mode_value_text(set, set.modes[0]), "0 Hz (rigid body)");
}

// Issue 48, item 6: a Ctrl-C while the mode pictures are drawn (after results.h5 had recorded the
// solve as completed) once left summary.json `interrupted` and results.h5 `completed`, and replay
// then reported a completed run. Both records now say the same status and reason.
TEST(ModeOutputs, CtrlCWhileModesAreDrawnIsOneOutcomeInBothRecords) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  std::atomic<bool> stop{false}, done{false};
  // Ctrl-C as soon as the first mode picture is on disk
  std::thread ctrl_c([&] {
    while (!done && !stop) {
      std::error_code ec;
      for (const auto& e : fs::recursive_directory_iterator(out, ec))
        if (e.path().extension() == ".png" && e.path().parent_path().filename().string().rfind("mode", 0) == 0)
          stop = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  const app::RunResult r = run_plate(out, true, false, "", -1, &stop);
  done = true;
  ctrl_c.join();
  ASSERT_TRUE(stop.load()) << "no mode picture was drawn";
  EXPECT_EQ(r.outcome.status, RunStatus::interrupted) << r.outcome.reason;
  EXPECT_NE(r.outcome.reason.find("mode pictures"), std::string::npos) << r.outcome.reason;
  std::string err;
  const auto h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  EXPECT_EQ(h5->outcome().status, r.outcome.status) << h5->outcome().reason;
  EXPECT_EQ(h5->outcome().reason, r.outcome.reason);
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_EQ(summary_string(*s, "status"), "interrupted");
  EXPECT_EQ(summary_string(*s, "reason"), r.outcome.reason);
}

}  // namespace
}  // namespace ff::cli::test
