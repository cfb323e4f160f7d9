// flexframe replay and the movie/export options: a diverged and an interrupted run replayed
// with another field, size and cadence (PNG count and size, the stored outcome reported), the
// MP4 read back through libavformat, the .vtu/.pvd read back through VTK and the .glb through
// assimp and compared with the HDF5 frames, `run --movie --export`, and bad input (exit 2),
// damaged files included.

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <csignal>
#include <random>

#include "app/frame_outputs.h"
#include "app/io/movie_writer.h"
#include "app/io/results.h"
#include "app/run_session.h"
#include "app/view_options.h"
#include "cli_support.h"
#include "tests/support/h5_damage.h"

namespace ff::cli::test {
namespace {

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

// the .glb's meshes ("surfaces" of triangles and quads, "lines") hold, in point order, exactly
// the points their cells use, at the frame's positions (float32)
void expect_glb_matches(const std::string& path, const FrameMesh& mesh, const Frame& f) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  const std::size_t n = mesh.point_count();
  std::vector<std::vector<std::int32_t>> used(2);  // surfaces, lines
  for (const auto* cells : {&mesh.triangles, &mesh.quads}) used[0].insert(used[0].end(), cells->begin(), cells->end());
  used[1] = mesh.lines;
  std::vector<std::vector<std::size_t>> expected;
  for (auto& u : used) {
    std::sort(u.begin(), u.end());
    u.erase(std::unique(u.begin(), u.end()), u.end());
    if (!u.empty()) expected.emplace_back(u.begin(), u.end());
  }
  ASSERT_EQ(scene->mNumMeshes, expected.size());
  double scale = 0;
  for (double p : f.points) scale = std::max(scale, std::fabs(p));
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    ASSERT_EQ(am->mNumVertices, expected[m].size()) << "mesh " << m << " of " << path;
    double diff = 0;
    for (std::size_t k = 0; k < expected[m].size(); ++k)
      for (int c = 0; c < 3; ++c) diff = std::max(diff, std::fabs(am->mVertices[k][c] - f.points[3 * expected[m][k] + c]));
    EXPECT_LE(diff, 1e-6 * scale) << "mesh " << m << " of " << path << " (glTF stores float32)";
    ASSERT_TRUE(am->HasTextureCoords(0)) << "the point index travels as texture coordinate u";
    for (std::size_t k = 0; k < expected[m].size(); ++k)
      ASSERT_EQ(am->mTextureCoords[0][k].x, static_cast<float>(expected[m][k])) << "vertex " << k;
  }
  std::size_t covered = 0;
  std::vector<bool> seen(n, false);
  for (const auto& e : expected)
    for (std::size_t i : e) covered += !seen[i], seen[i] = true;
  EXPECT_EQ(covered, n) << "every point of the frame is in the file";
}

// the diverging zero-order hub-beam (stops at t = 1.77 s, 178 frames, well under a second)
std::string diverged_run(const std::string& dir) {
  const std::string out = dir + "/run";
  const ProcResult r = run_flexframe({"run", "hub_beam_zero_order_tau10", "--out", out, "--quiet", "--no-frames",
                                      "--no-plots"},
                                     dir + "/run");
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  return out;
}

TEST(ReplayOptions, CameraSizeFormatsAndSelection) {
  EXPECT_TRUE(app::parse_camera("auto").automatic);
  EXPECT_EQ(app::parse_camera("auto").view_direction, (std::array<double, 3>{0, 0, 0}));
  // directions as unit vectors (the command line and the scene timeline share one parser)
  const auto expect_along = [](const std::array<double, 3>& got, std::array<double, 3> want) {
    const double n = std::sqrt(want[0] * want[0] + want[1] * want[1] + want[2] * want[2]);
    for (int k = 0; k < 3; ++k) { EXPECT_NEAR(got[k], want[k] / n, 1e-12) << k; }
  };
  expect_along(app::parse_camera("iso").view_direction, {1, -1, 1});
  const render::Camera top = app::parse_camera("top,2.5");
  expect_along(top.view_direction, {0, 0, 1});
  expect_along(top.view_up, {0, 1, 0});
  EXPECT_EQ(top.zoom, 2.5);
  const render::Camera ae = app::parse_camera("90,0,0.5");  // azimuth 90: the eye on +y
  EXPECT_NEAR(ae.view_direction[0], 0, 1e-12);
  EXPECT_NEAR(ae.view_direction[1], 1, 1e-12);
  EXPECT_NEAR(ae.view_direction[2], 0, 1e-12);
  EXPECT_EQ(ae.zoom, 0.5);
  EXPECT_NEAR(app::parse_camera("0,90").view_direction[2], 1, 1e-12);
  for (const char* bad : {"", "north", "10", "10,95", "iso,0", "iso,2,3", "1,2,3,4", "iso,x"})
    EXPECT_THROW(app::parse_camera(bad), app::InputError) << bad;
  EXPECT_EQ(app::parse_size("1280x720"), (std::pair<int, int>{1280, 720}));
  for (const char* bad : {"1280", "x720", "63x100", "100x9000", "12.5x100", "axb"})
    EXPECT_THROW(app::parse_size(bad), app::InputError) << bad;
  const app::ExportFormats f = app::parse_export_formats("vtu,gltf");
  EXPECT_TRUE(f.vtu && f.gltf && !f.obj);
  EXPECT_THROW(app::parse_export_formats(""), app::InputError);
  EXPECT_EQ(app::frame_selection(10, 4, true), (std::vector<std::size_t>{0, 4, 8, 9}));
  EXPECT_EQ(app::frame_selection(10, 4, false), (std::vector<std::size_t>{0, 4, 8}));
  EXPECT_EQ(app::frame_selection(9, 4, true), (std::vector<std::size_t>{0, 4, 8}));
  EXPECT_TRUE(app::frame_selection(0, 1, true).empty());
}

TEST(CliReplay, DivergedRunWithAnotherFieldSizeMovieAndExports) {
  const std::string dir = fresh_test_dir();
  const std::string run = diverged_run(dir);
  std::string err;
  const auto h5 = io::ResultReader::open(run + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const std::size_t stored = h5->frame_count();
  ASSERT_GT(stored, 100u);
  const RunOutcome outcome = h5->outcome();
  ASSERT_EQ(outcome.status, RunStatus::diverged);

  const std::string out = dir + "/replay";
  const ProcResult r = run_flexframe({"replay", run + "/results.h5", "--out", out, "--field", "transverse", "--size",
                                      "320x240", "--frame-every", "40", "--movie", "--fps", "10", "--export",
                                      "vtu,gltf", "--camera", "top,1.2"},
                                     dir + "/replay");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  // how far the stored run got, and why it stopped
  EXPECT_NE(r.out.find("diverged at t = 1.77"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(outcome.reason), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(std::to_string(stored) + " stored frames"), std::string::npos) << r.out;

  // every 40th stored frame and the last: 0, 40, 80, 120, 160, 177
  const std::vector<std::size_t> selection = app::frame_selection(stored, 40, true);
  ASSERT_EQ(selection.size(), (stored - 1) / 40 + 1 + ((stored - 1) % 40 != 0));
  const auto pngs = pngs_in(out + "/frames");
  ASSERT_EQ(pngs.size(), selection.size());
  for (const std::string& p : pngs) {
    const Image img = read_png(p);
    EXPECT_EQ(img.width, 320) << p;
    EXPECT_EQ(img.height, 240) << p;
  }
  EXPECT_TRUE(fs::is_regular_file(out + "/plots/hub_angle.png"));

  // the movie: one video frame per PNG, at the PNG size
  io::MovieInfo movie;
  ASSERT_TRUE(io::probe_movie(out + "/movie.mp4", &movie, &err)) << err;
  EXPECT_EQ(movie.frames, static_cast<int>(pngs.size()));
  EXPECT_EQ(movie.width, 320);
  EXPECT_EQ(movie.height, 240);
  EXPECT_NEAR(movie.fps, 10.0, 1e-9);
  EXPECT_EQ(movie.codec, "h264");

  // the collection lists one .vtu per replayed frame with the stored times
  const std::string pvd = read_text(out + "/export/hub_beam_zero_order_tau10.pvd");
  EXPECT_EQ(count_of(pvd, "<DataSet "), selection.size()) << pvd;
  const std::vector<double> times = h5->times();
  const std::size_t n = h5->info().mesh.point_count();
  const int transverse = app::field_index(h5->info(), "transverse");
  ASSERT_GE(transverse, 0);
  for (std::size_t k = 0; k < selection.size(); ++k) {
    SCOPED_TRACE("exported frame " + std::to_string(k) + " = stored frame " + std::to_string(selection[k]));
    char stem[32];
    std::snprintf(stem, sizeof stem, "frame_%05zu", k);
    EXPECT_NE(pvd.find(std::string("file=\"") + stem + ".vtu\""), std::string::npos);
    const Frame f = h5->frame(selection[k]);

    vtkNew<vtkXMLUnstructuredGridReader> vtu;
    vtu->SetFileName((out + "/export/" + stem + ".vtu").c_str());
    vtu->Update();
    vtkUnstructuredGrid* grid = vtu->GetOutput();
    ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(n));
    double max_diff = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double p[3];
      grid->GetPoint(static_cast<vtkIdType>(i), p);
      for (int c = 0; c < 3; ++c) max_diff = std::max(max_diff, std::fabs(p[c] - f.points[3 * i + c]));
    }
    EXPECT_EQ(max_diff, 0.0) << "VTU points are doubles, bit for bit";
    vtkDataArray* field = grid->GetPointData()->GetArray("transverse");
    ASSERT_NE(field, nullptr);
    for (std::size_t i = 0; i < n; ++i)
      ASSERT_EQ(field->GetTuple1(static_cast<vtkIdType>(i)), f.fields[transverse][i]) << "point " << i;
    ASSERT_NE(grid->GetPointData()->GetArray("deflection"), nullptr);
    vtkDataArray* time = grid->GetFieldData()->GetArray("TimeValue");
    ASSERT_NE(time, nullptr);
    EXPECT_EQ(time->GetTuple1(0), times[selection[k]]);
    EXPECT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(h5->info().mesh.lines.size() / 2 +
                                                                h5->info().mesh.triangles.size() / 3 +
                                                                h5->info().mesh.quads.size() / 4));

    expect_glb_matches(out + "/export/" + stem + ".glb", h5->info().mesh, f);
  }
}

TEST(CliReplay, InterruptedRunSaysHowFarItGot) {
  const std::string dir = fresh_test_dir();
  const std::string run = dir + "/run";
  // 60 s of simulated time at dt = 2 ms: far longer than the test waits; stopped with SIGINT
  Child child({"run", "hub_beam_converged_tau1", "--out", run, "--no-plots", "--no-frames", "--quiet", "--set",
               "solver.end=60"},
              dir + "/run");
  ASSERT_TRUE(child.started());
  const auto t0 = std::chrono::steady_clock::now();
  const auto waited = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  while (!fs::exists(run + "/results.h5") && child.running() && waited() < 30)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_TRUE(child.running()) << child.wait(1).describe();
  ASSERT_TRUE(child.send(SIGINT));
  const ProcResult stopped = child.wait(30);
  ASSERT_EQ(stopped.exit_code, 130) << stopped.describe();

  std::string err;
  const auto h5 = io::ResultReader::open(run + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const std::size_t stored = h5->frame_count();
  ASSERT_GT(stored, 2u);
  const RunOutcome outcome = h5->outcome();
  ASSERT_EQ(outcome.status, RunStatus::interrupted);

  // replaying the run folder: default output <run>/replay, the run's field and size
  const int every = static_cast<int>(stored / 4 + 1);
  const ProcResult r = run_flexframe({"replay", run, "--frame-every", std::to_string(every), "--no-plots"},
                                     dir + "/replay");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::ostringstream when;
  when << "interrupted at t = " << outcome.stop_time;
  EXPECT_NE(r.out.find(when.str()), std::string::npos) << "expected '" << when.str() << "' in\n" << r.out;
  EXPECT_NE(r.out.find("reason: "), std::string::npos) << r.out;
  const auto pngs = pngs_in(run + "/replay/frames");
  EXPECT_EQ(pngs.size(), app::frame_selection(stored, every, true).size());
  const Image img = read_png(pngs.back());
  EXPECT_EQ(img.width, 960);
  EXPECT_EQ(img.height, 720);
  EXPECT_FALSE(fs::exists(run + "/replay/plots/hub_angle.png"));
}

TEST(CliReplay, RunWithMovieAndExport) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe({"run", "hub_beam_fem_tau1", "--out", out, "--quiet", "--no-plots", "--set",
                                      "solver.end=0.5", "--frame-every", "2", "--width", "322", "--height", "241",
                                      "--movie", "--export", "vtu,obj", "--camera", "-90,0"},
                                     dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.describe();
  // 11 frames, every 2nd rendered and exported: 0, 2, ..., 10
  const auto pngs = pngs_in(out + "/frames");
  ASSERT_EQ(pngs.size(), 6u);
  std::string err;
  io::MovieInfo movie;
  ASSERT_TRUE(io::probe_movie(out + "/movie.mp4", &movie, &err)) << err;
  EXPECT_EQ(movie.frames, 6);
  EXPECT_EQ(movie.width, 322);  // odd sizes are padded to even ones for yuv420p
  EXPECT_EQ(movie.height, 242);
  EXPECT_EQ(count_of(read_text(out + "/export/hub_beam_fem_tau1.pvd"), "<DataSet "), 6u);
  EXPECT_TRUE(fs::is_regular_file(out + "/export/frame_00005.obj"));
  EXPECT_FALSE(fs::exists(out + "/export/frame_00006.vtu"));
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  const Json* outputs = s->get("outputs");
  ASSERT_TRUE(outputs && outputs->get("movie") && outputs->get("export_frames"));
  EXPECT_EQ(outputs->get("movie")->string, "movie.mp4");
  EXPECT_EQ(outputs->get("export_frames")->number, 6);

  // the OBJ holds the frame's points (assimp reads it back; 'l' lines and triangles)
  const auto h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const Frame f = h5->frame(10);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(out + "/export/frame_00005.obj", 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  std::size_t vertices = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) vertices += scene->mMeshes[m]->mNumVertices;
  EXPECT_GT(vertices, 0u);
  // every imported vertex is one of the frame's points
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    for (unsigned v = 0; v < scene->mMeshes[m]->mNumVertices; ++v) {
      const aiVector3D& p = scene->mMeshes[m]->mVertices[v];
      double best = 1e300;
      for (std::size_t i = 0; i < f.points.size() / 3; ++i)
        best = std::min(best, std::fabs(p.x - f.points[3 * i]) + std::fabs(p.y - f.points[3 * i + 1]) +
                                  std::fabs(p.z - f.points[3 * i + 2]));
      ASSERT_LT(best, 1e-5) << "vertex " << v << " of mesh " << m;
    }
}

TEST(CliReplay, ShellExportKeepsEveryNodeInOrder) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  std::vector<std::string> args{"run", "double_pendulum_shells", "--out", out, "--quiet", "--no-frames", "--no-plots",
                                "--export", "gltf,vtu", "--set", "solver.end=0.003", "--set", "solver.output_every=2"};
  for (const char* k : {"part[0].n1=3", "part[0].n2=3", "part[1].n1=3", "part[1].n2=3", "output.frame_every=2"})
    args.insert(args.end(), {"--set", k});
  const ProcResult r = run_flexframe(args, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string err;
  const auto h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const auto selection = app::frame_selection(h5->frame_count(), 2, false);
  ASSERT_GE(selection.size(), 2u);
  const std::size_t n = h5->info().mesh.point_count();
  for (std::size_t k = 0; k < selection.size(); ++k) {
    char stem[48];
    std::snprintf(stem, sizeof stem, "/export/frame_%05zu", k);
    const Frame f = h5->frame(selection[k]);
    expect_glb_matches(out + stem + ".glb", h5->info().mesh, f);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(out + stem + ".glb", 0);
    ASSERT_TRUE(scene && scene->mNumMeshes == 1);
    EXPECT_EQ(scene->mMeshes[0]->mNumVertices, n) << "a quad mesh over all nodes: vertex i = node i";
    vtkNew<vtkXMLUnstructuredGridReader> vtu;
    vtu->SetFileName((out + stem + ".vtu").c_str());
    vtu->Update();
    EXPECT_EQ(vtu->GetOutput()->GetNumberOfPoints(), static_cast<vtkIdType>(n));
    EXPECT_EQ(vtu->GetOutput()->GetNumberOfCells(), static_cast<vtkIdType>(h5->info().mesh.quads.size() / 4));
  }
  EXPECT_FALSE(fs::exists(out + "/export/frame_" + std::string(5 - std::to_string(selection.size()).size(), '0') +
                          std::to_string(selection.size()) + ".glb"));
}

TEST(CliReplay, BadInputExitsTwoWithAClearMessage) {
  const std::string dir = fresh_test_dir();
  const std::string run = diverged_run(dir);
  const std::string h5 = run + "/results.h5";
  write_text(dir + "/not_hdf5.h5", "this is text, not HDF5\n");
  {  // an HDF5 file that is not a results file
    const hid_t f = H5Fcreate((dir + "/plain.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Fclose(f);
  }
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"replay", dir + "/missing.h5"}, "no such file"},
      {{"replay", dir + "/not_hdf5.h5"}, "not an HDF5 file"},
      {{"replay", dir + "/plain.h5"}, "not a FlexFrame results file"},
      {{"replay", h5, "--field", "stress"}, "available: deflection, transverse"},
      {{"replay", h5, "--size", "800"}, "WIDTHxHEIGHT"},
      {{"replay", h5, "--size", "10x10"}, "64..8192"},
      {{"replay", h5, "--camera", "north"}, "AZIMUTH,ELEVATION"},
      {{"replay", h5, "--camera", "iso,-1"}, "zoom"},
      {{"replay", h5, "--export", "vtu,stl"}, "unknown format 'stl'"},
      {{"replay", h5, "--frame-every", "0"}, "frame-every"},
      {{"run", "hub_beam_fem_tau1", "--out", dir + "/never", "--camera", "sideways"}, "AZIMUTH,ELEVATION"},
      {{"run", "hub_beam_fem_tau1", "--out", dir + "/never", "--export", "png"}, "unknown format 'png'"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::vector<std::string> args = c.args[0] == "replay" && c.args.size() > 2
                                              ? [&] { auto a = c.args; a.insert(a.end(), {"--out", dir + "/never"}); return a; }()
                                              : c.args;
    const ProcResult r = run_flexframe(args, dir + "/case" + std::to_string(i));
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_EQ(r.signal, 0) << r.describe();
    EXPECT_NE(r.err.find(c.message), std::string::npos) << "expected '" << c.message << "'\n" << r.describe();
  }
  EXPECT_FALSE(fs::exists(dir + "/never")) << "bad input must not write anything";
}

// a short finished run of hub_beam_fem_tau1 (11 frames, t = 0 .. 0.5 s); its results.h5
std::string short_run(const std::string& dir) {
  const ProcResult r = run_flexframe({"run", "hub_beam_fem_tau1", "--out", dir + "/run", "--quiet", "--no-frames",
                                      "--no-plots", "--set", "solver.end=0.5"},
                                     dir + "/run");
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  return dir + "/run/results.h5";
}

// issue 12, finding 9: a block of frame data zeroed, randomised or 0xFF-filled used to replay
// with exit 0; now it is bad input named by file, data set and frame, and nothing is written
TEST(CliReplay, DamagedFrameDataExitsTwoNamingDataSetAndFrame) {
  const std::string dir = fresh_test_dir();
  const std::string good = short_run(dir);
  std::string err;
  std::size_t row_bytes = 0;
  {
    const auto h5 = io::ResultReader::open(good, &err);
    ASSERT_TRUE(h5) << err;
    ASSERT_EQ(h5->frame_count(), 11u);
    EXPECT_EQ(h5->verify(), "");
    row_bytes = 24 * h5->info().mesh.point_count();
  }
  std::mt19937 rng(12);
  for (const std::string kind : {"zeroed", "random", "ff"}) {
    const std::string run = dir + "/" + kind, h5 = run + "/results.h5";
    fs::create_directories(run);
    fs::copy_file(good, h5);
    std::vector<unsigned char> block(row_bytes / 2, kind == "zeroed" ? 0x00 : 0xFF);
    if (kind == "random")
      for (auto& b : block) b = static_cast<unsigned char>(rng());
    ff::test::overwrite(h5, ff::test::chunk_row_offset(h5, "/frames/points", 5) + row_bytes / 4, block);
    const ProcResult r = run_flexframe({"replay", run, "--no-plots"}, dir + "/replay_" + kind);
    EXPECT_EQ(r.exit_code, 2) << kind << ": " << r.describe();
    EXPECT_NE(r.err.find("results file '" + h5 + "'"), std::string::npos) << kind << ": " << r.describe();
    EXPECT_NE(r.err.find("data set '/frames/points'"), std::string::npos) << kind << ": " << r.describe();
    EXPECT_NE(r.err.find("frame 5 of 11 (t = 0.25 s)"), std::string::npos) << kind << ": " << r.describe();
    EXPECT_EQ(r.err.find("infinite loop"), std::string::npos) << kind << ": " << r.describe();
    EXPECT_FALSE(fs::exists(run + "/replay")) << kind << ": bad input must not write anything";
  }
}

// issue 12, finding 10: a damaged metadata checksum gave the right error, then HDF5's "infinite
// loop closing library" (its shutdown after the leak of its failed object-header load)
TEST(CliReplay, DamagedMetadataChecksumGivesOneCleanMessage) {
  const std::string dir = fresh_test_dir();
  const std::string good = short_run(dir);
  const std::string run = dir + "/damaged", h5 = run + "/results.h5";
  fs::create_directories(run);
  fs::copy_file(good, h5);
  const auto at = ff::test::object_header_checksum_offset(h5, "/outcome");
  std::vector<unsigned char> sum = ff::test::read_bytes(h5, at, 4);
  ASSERT_EQ(sum.size(), 4u);
  for (auto& b : sum) b = static_cast<unsigned char>(~b);
  ff::test::overwrite(h5, at, sum);
  const ProcResult r = run_flexframe({"replay", run, "--no-plots"}, dir + "/replay");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("results file '" + h5 + "'"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("'/outcome'"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("incorrect metadata checksum"), std::string::npos) << r.describe();
  EXPECT_EQ(r.err.find("infinite loop"), std::string::npos) << r.describe();
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "only the error line:\n" << r.err;
  EXPECT_FALSE(fs::exists(run + "/replay"));
}

// issue 30, item 6: a results file without a frame replayed with exit 0 and "nothing to replay";
// replay can make none of what it was asked for, so it is bad input (exit 2, the file and the
// stored run named) and nothing is written
TEST(CliReplay, AFileWithoutFramesIsBadInput) {
  const std::string dir = fresh_test_dir();
  const std::string good = short_run(dir);
  std::string err;
  const auto h5 = io::ResultReader::open(good, &err);
  ASSERT_TRUE(h5) << err;
  const std::string run = dir + "/empty", empty = run + "/results.h5";
  fs::create_directories(run);
  {  // the run's own description, then the end of a run that diverged before its first frame
    const auto w = io::ResultWriter::create(empty, h5->info(), &err);
    ASSERT_TRUE(w) << err;
    RunOutcome outcome;
    outcome.status = RunStatus::diverged;
    outcome.reason = "singular matrix at the first step";
    ASSERT_TRUE(w->finish(outcome, {}, &err)) << err;
  }
  const ProcResult r = run_flexframe({"replay", run}, dir + "/replay");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find(empty + " holds no complete frame: nothing to replay (stored run: diverged after 0 steps)"),
            std::string::npos)
      << r.describe();
  EXPECT_FALSE(fs::exists(run + "/replay")) << "bad input must not write anything";
}

// Issue 48, item 9: a results file from someone else names where replay and compare write.
// A probe named "/<dir>/evil" (its data set at that path in the file) once made replay write the
// plot <dir>/evil.png outside --out, and a stored scene name "<dir>/pvd_victim" the export
// <dir>/pvd_victim.pvd. Both files are refused as bad input (exit 2) before anything is written.
void rewrite_string_attribute(const std::string& file, const std::string& object, const std::string& name,
                              const std::vector<std::string>& values) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t o = H5Oopen(f, object.c_str(), H5P_DEFAULT);
  ASSERT_GE(o, 0);
  if (H5Aexists(o, name.c_str()) > 0) H5Adelete(o, name.c_str());
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  const hsize_t n = values.size();
  const hid_t space = values.size() == 1 && name != "names" ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr);
  const hid_t a = H5Acreate2(o, name.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<const char*> p;
  for (const std::string& v : values) p.push_back(v.c_str());
  EXPECT_GE(H5Awrite(a, t, p.data()), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(t);
  H5Oclose(o);
  H5Fclose(f);
}

TEST(CliReplay, NamesInAStrangersResultsFileNeverLeaveOut) {
  const std::string dir = fresh_test_dir();
  const std::string run = dir + "/run", victim = dir + "/victim";
  ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", run, "--quiet", "--no-frames"}, run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  fs::create_directories(victim);
  write_text(victim + "/evil.png", "precious\n");
  write_text(victim + "/pvd_victim.pvd", "precious\n");

  // a probe whose name is an absolute path, its data set linked there inside the file
  const std::string probe_file = dir + "/evil_probe.h5";
  fs::copy_file(run + "/results.h5", probe_file);
  {
    const hid_t f = H5Fopen(probe_file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    ASSERT_GE(H5Lcreate_hard(f, "/frames/probes/w_centre", f, (victim + "/evil").c_str(), lcpl, H5P_DEFAULT), 0);
    H5Pclose(lcpl);
    H5Fclose(f);
  }
  rewrite_string_attribute(probe_file, "/frames/probes", "names", {"lambda", victim + "/evil"});
  // a scene name that is a path
  const std::string scene_file = dir + "/evil_scene.h5";
  fs::copy_file(run + "/results.h5", scene_file);
  rewrite_string_attribute(scene_file, "/run", "scene_name", {victim + "/pvd_victim"});

  for (const auto& [file, what] : {std::pair{probe_file, std::string("the probe name '")},
                                   std::pair{scene_file, std::string("the scene name '")}}) {
    SCOPED_TRACE(file);
    r = run_flexframe({"replay", file, "--out", dir + "/replay", "--export", "vtu"}, dir + "/replay");
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find(what + victim), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("contains the path separator '/'"), std::string::npos) << r.describe();
    r = run_flexframe({"compare", file, run, "--out", dir + "/compare"}, dir + "/compare");
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find(what + victim), std::string::npos) << r.describe();
  }
  EXPECT_EQ(read_text(victim + "/evil.png"), "precious\n");
  EXPECT_EQ(read_text(victim + "/pvd_victim.pvd"), "precious\n");
  EXPECT_EQ(tree(victim), (std::vector<std::string>{"evil.png", "pvd_victim.pvd"}));
}

}  // namespace
}  // namespace ff::cli::test
