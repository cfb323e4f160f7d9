// Issue 30, findings 1-3: nothing a user owns is at risk from a run, a replay or a study.
// - A scene or study name that is not one plain folder name (a separator, "..", an absolute
//   path) is refused at its line, before anything is written; planted folders survive.
// - A job deletes only what earlier flexframe jobs recorded in the folder's manifest: a user's
//   files in frames/ or runs/ survive a run or a new study in the same folder.
// - A second job on the same folder is refused before it touches any file (runs and studies).
// - A full disk ends `failed` (exit 1) with "disk full", never `completed`, and what was stored
//   before stays readable (a small tmpfs; skipped with the reason where it cannot be mounted).

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

std::string scene_with_name(const std::string& bundled, const std::string& name) {
  std::string text = read_text(scene_path(bundled));
  const std::size_t at = text.find("\nname = ");
  EXPECT_NE(at, std::string::npos) << bundled << " has no top-level name line";
  const std::size_t end = text.find('\n', at + 1);
  return text.substr(0, at) + "\nname = \"" + name + "\"" + text.substr(end);
}

// the 1-based line of the first occurrence of `needle` in `text`
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  return at == std::string::npos ? -1 : 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
}

double output_frames(const Json& s) {
  const Json* o = s.get("outputs");
  const Json* f = o ? o->get("frames") : nullptr;
  return f && f->is_number() ? f->number : std::nan("");
}

void plant(const std::string& file) {
  fs::create_directories(fs::path(file).parent_path());
  write_text(file, "a user's file\n");
}

TEST(CliOutputSafety, SceneNameThatLeavesOutIsRefusedAtItsLine) {
  const std::string dir = fresh_test_dir();
  const std::string work = dir + "/work";
  fs::create_directories(work);
  plant(dir + "/victim/frames/keep.png");  // where out/../../victim would land, seen from work/
  for (const std::string& name : std::vector<std::string>{"../../victim", dir + "/victim", "a/b", "..", "a..b", ""}) {
    const std::string scene = work + "/s.toml";
    const std::string text = scene_with_name("hub_beam_converged_tau1", name);
    write_text(scene, text);
    for (const char* verb : {"check", "run"}) {
      const ProcResult r = run_flexframe({verb, scene}, dir + "/" + verb, work);
      EXPECT_EQ(r.exit_code, 2) << "name '" << name << "'\n" << r.describe();
      EXPECT_NE(r.err.find("scene.name"), std::string::npos) << r.describe();
      EXPECT_NE(r.err.find("s.toml:" + std::to_string(line_of(text, "\nname = ") + 1)), std::string::npos)
          << "the message names the file and the key's line\n" << r.describe();
    }
    EXPECT_TRUE(fs::is_regular_file(dir + "/victim/frames/keep.png")) << name;
    EXPECT_FALSE(fs::exists(work + "/out")) << "nothing is written for a refused scene";
  }
}

TEST(CliOutputSafety, StudyNameThatLeavesOutIsRefusedAndPlantedRunsSurvive) {
  const std::string dir = fresh_test_dir();
  const std::string work = dir + "/work";
  plant(work + "/out/victim/runs/keep.txt");  // out/study/../victim/runs used to be removed whole
  const std::string study = work + "/s.toml";
  const std::string text = "[study]\nname = \"../victim\"\nscene = \"hub_beam_converged_tau1\"\n"
                           "metric = \"tip_transverse_at_2s_m\"\n\n[[vary]]\nkey = [\"solver.end\"]\n"
                           "values = [\"0.01\", \"0.02\"]\n\n[reference]\nkind = \"finest\"\n";
  write_text(study, text);
  for (const bool check : {true, false}) {
    std::vector<std::string> args{"study", study};
    if (check) args.push_back("--check");
    const ProcResult r = run_flexframe(args, dir + "/study", work);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("study.name"), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("s.toml:2"), std::string::npos) << r.describe();
  }
  EXPECT_TRUE(fs::is_regular_file(work + "/out/victim/runs/keep.txt"));
  EXPECT_FALSE(fs::exists(work + "/out/study"));
}

// A user's own files in an output folder survive a run, a replay and a new study there; what an
// earlier run of flexframe wrote (frames beyond the new run's count) is removed.
TEST(CliOutputSafety, OnlyRecordedFilesAreDeleted) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/mine";
  plant(out + "/frames/user.png");
  plant(out + "/plots/user.png");
  plant(out + "/notes.txt");
  // a longer run first, then a shorter one: the first run's extra frames must go
  ProcResult r = run_flexframe({"run", "hub_beam_converged_tau1", "--out", out, "--set", "solver.end=0.2",
                                "--frame-every", "10", "--no-plots"},
                               dir + "/long");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::size_t long_frames = pngs_in(out + "/frames").size();
  r = run_flexframe({"run", "hub_beam_converged_tau1", "--out", out, "--set", "solver.end=0.05", "--frame-every",
                     "10", "--no-plots"},
                    dir + "/short");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::size_t short_frames = pngs_in(out + "/frames").size();
  EXPECT_LT(short_frames, long_frames) << "the longer run's frames were not removed";
  EXPECT_NE(r.err.find("1 PNG file(s)"), std::string::npos) << "the user's PNG is mentioned\n" << r.describe();
  for (const char* f : {"/frames/user.png", "/plots/user.png", "/notes.txt"})
    EXPECT_TRUE(fs::is_regular_file(out + f)) << f;
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_EQ(output_frames(*s) + 1, static_cast<double>(short_frames))
      << "frames/ holds this run's frames and the user's one";

  // a replay into the same kind of folder
  plant(out + "/replay/frames/user.png");
  r = run_flexframe({"replay", out + "/results.h5", "--no-plots"}, dir + "/replay");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_TRUE(fs::is_regular_file(out + "/replay/frames/user.png"));

  // a study whose folder holds a user's files in runs/: a new (not resumed) study keeps them
  const std::string study_out = dir + "/study";
  plant(study_out + "/runs/000/mine.txt");
  plant(study_out + "/runs/user/keep.txt");
  const std::string study = dir + "/s.toml";
  write_text(study, "[study]\nscene = \"hub_beam_converged_tau1\"\nmetric = \"tip_transverse_at_2s_m\"\n"
                    "set = [\"solver.end=2\"]\n\n[[vary]]\nkey = [\"solver.dt\"]\nvalues = [\"0.004\", \"0.008\"]\n\n[reference]\nkind = \"finest\"\n");
  for (int k = 0; k < 2; ++k) {
    r = run_flexframe({"study", study, "--out", study_out}, dir + "/study" + std::to_string(k), "", 120);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }
  EXPECT_TRUE(fs::is_regular_file(study_out + "/runs/000/mine.txt"));
  EXPECT_TRUE(fs::is_regular_file(study_out + "/runs/user/keep.txt"));
  EXPECT_TRUE(fs::is_regular_file(study_out + "/runs/001/summary.json"));
}

// The second job on a folder is refused before it touches anything: the first keeps its results
// file, and every frame it reports is there at the end.
TEST(CliOutputSafety, SecondRunOnTheSameFolderIsRefusedBeforeTouchingIt) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  Child first({"run", "hub_beam_converged_tau1", "--out", out, "--no-plots", "--frame-every", "25", "--set",
               "solver.end=60"},
              dir + "/first");
  ASSERT_TRUE(first.started());
  const auto t0 = std::chrono::steady_clock::now();
  const auto waited = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  // frames are drawn after the solve: what shows the first run at work is its results file, which
  // it creates under its lock before the solve starts and fills while it solves
  const std::string h5 = out + "/results.h5";
  const auto h5_size = [&] {
    std::error_code ec;
    const auto n = fs::file_size(h5, ec);
    return ec ? std::uintmax_t{0} : n;
  };
  while (h5_size() == 0 && first.running() && waited() < 120)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_GT(h5_size(), 0u) << first.wait(1).describe();
  struct stat before;
  ASSERT_EQ(::stat(h5.c_str(), &before), 0);
  const ProcResult second = run_flexframe({"run", "hub_beam_converged_tau1", "--out", out}, dir + "/second");
  EXPECT_EQ(second.exit_code, 1) << second.describe();
  EXPECT_NE(second.err.find("in use by flexframe run (pid " + std::to_string(first.pid()) + ")"), std::string::npos)
      << second.describe();
  struct stat after;
  ASSERT_EQ(::stat(h5.c_str(), &after), 0) << "the second run deleted the first's results file";
  EXPECT_EQ(after.st_ino, before.st_ino) << "the second run replaced the first's results file";
  EXPECT_GE(after.st_size, before.st_size) << "the second run truncated the first's results file";
  ASSERT_TRUE(first.send(SIGINT));
  const ProcResult r = first.wait(120);
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_GT(output_frames(*s), 0.0) << "the frames the first run computed are drawn after its Ctrl-C";
  EXPECT_EQ(output_frames(*s), static_cast<double>(pngs_in(out + "/frames").size()))
      << "every frame the first run reports is there";
}

TEST(CliOutputSafety, SecondStudyOnTheSameFolderIsRefused) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/study";
  const std::string study = dir + "/s.toml";
  write_text(study, "[study]\nscene = \"hub_beam_converged_tau1\"\nmetric = \"tip_transverse_at_2s_m\"\n"
                    "set = [\"solver.end=30\"]\n\n[[vary]]\nkey = [\"solver.dt\"]\nvalues = [\"0.002\", \"0.004\"]\n\n[reference]\nkind = \"finest\"\n");
  Child first({"study", study, "--out", out, "--jobs", "1"}, dir + "/first");
  ASSERT_TRUE(first.started());
  const auto t0 = std::chrono::steady_clock::now();
  const auto waited = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  while (!fs::exists(out + "/runs/000") && first.running() && waited() < 60)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(out + "/runs/000")) << first.wait(1).describe();
  ASSERT_TRUE(first.running()) << "the first study ended before the second started";
  const ProcResult second = run_flexframe({"study", study, "--out", out}, dir + "/second");
  EXPECT_EQ(second.exit_code, 1) << second.describe();
  EXPECT_NE(second.err.find("in use by flexframe study"), std::string::npos) << second.describe();
  EXPECT_TRUE(fs::exists(out + "/runs/000")) << "the second study emptied the first's runs/";
  first.send(SIGINT);
  EXPECT_EQ(first.wait(60).exit_code, 130);
}

// ---- a full disk -----------------------------------------------------------------------------

void expect_disk_full_failure(const ProcResult& r) {
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_EQ(r.signal, 0) << "killed by a signal on its way out\n" << r.describe();
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.describe();
}

TEST(CliOutputSafety, FullDiskEndsTheRunFailedAndKeepsWhatWasStored) {
  const std::string dir = fresh_test_dir();
  SmallDisk disk(dir + "/tiny", 4096);
  if (!disk.mounted()) GTEST_SKIP() << disk.why();
  const std::string out = dir + "/tiny/out";
  const ProcResult r = run_flexframe({"run", "hub_beam_converged_tau1", "--out", out, "--frame-every", "1", "--set",
                                      "solver.end=10"},
                                     dir + "/run", "", 120);
  expect_disk_full_failure(r);
  EXPECT_EQ(r.out.find("completed"), std::string::npos) << r.describe();
  // what was stored before is readable: results.h5 opens with its frames
  std::string err;
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  EXPECT_GT(h5->frame_count(), 0u);
  EXPECT_NE(h5->outcome().status, RunStatus::completed);
  // the file holds the outcome, and the console does not say otherwise (it once printed "could
  // not record the outcome: ... (the outcome is recorded; ...)" when frames were lost)
  EXPECT_EQ(h5->outcome().status, RunStatus::failed) << h5->outcome().reason;
  EXPECT_EQ(r.err.find("could not record the outcome"), std::string::npos) << r.describe();
  // the summary, where it could still be written, says failed
  if (const std::optional<Json> s = read_summary(out, &err)) {
    EXPECT_EQ(summary_string(*s, "status"), "failed");
    EXPECT_NE(summary_string(*s, "reason").find("disk full"), std::string::npos);
  }
}

TEST(CliOutputSafety, FullDiskFailsTheStudyReplayMovieAndExport) {
  const std::string dir = fresh_test_dir();
  // a stored run on the ordinary disk to replay
  const std::string run = dir + "/run";
  ProcResult r = run_flexframe({"run", "hub_beam_converged_tau1", "--out", run, "--set", "solver.end=1", "--no-plots"},
                               dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  SmallDisk disk(dir + "/tiny", 1024);
  if (!disk.mounted()) GTEST_SKIP() << disk.why();
  r = run_flexframe({"replay", run + "/results.h5", "--out", dir + "/tiny/replay", "--movie", "--frame-every", "1"},
                    dir + "/replay", "", 120);
  expect_disk_full_failure(r);
  fs::remove_all(dir + "/tiny/replay");
  r = run_flexframe({"replay", run + "/results.h5", "--out", dir + "/tiny/export", "--no-frames", "--no-plots",
                     "--export", "vtu,obj", "--frame-every", "1"},
                    dir + "/export", "", 120);
  expect_disk_full_failure(r);
  fs::remove_all(dir + "/tiny/export");
  const std::string study = dir + "/s.toml";
  write_text(study, "[study]\nscene = \"hub_beam_converged_tau1\"\nmetric = \"tip_transverse_at_2s_m\"\n"
                    "set = [\"solver.end=2\"]\n\n[[vary]]\nkey = [\"solver.dt\"]\nvalues = [\"0.004\", \"0.008\"]\n\n[reference]\nkind = \"finest\"\n");
  // fill the disk but for a few bytes: the study's tables cannot be written
  {
    std::ofstream fill(dir + "/tiny/fill", std::ios::binary);
    const std::string block(4096, 'x');
    while (fill << block && fill.flush()) {
    }
  }
  r = run_flexframe({"study", study, "--out", dir + "/tiny/study"}, dir + "/study", "", 120);
  expect_disk_full_failure(r);
}

// Issue 48, item 6: the two records of a run say one outcome. A disk that fills after the solve
// (while the frames and plots are written, after results.h5 had recorded `completed`) once left
// summary.json `failed` and results.h5 `completed` with no frame, and replay then reported the
// stored run as completed. Both now say `failed`, with the same reason, whatever the fill.
void expect_one_outcome(const std::string& out, const ProcResult& r) {
  std::string err;
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err << "\n" << r.describe();
  const std::optional<Json> s = read_summary(out, &err);
  if (!s) {  // no summary.json: the file alone must not claim success
    EXPECT_NE(h5->outcome().status, RunStatus::completed) << h5->outcome().reason << "\n" << r.describe();
    return;
  }
  EXPECT_EQ(summary_string(*s, "status"), to_string(h5->outcome().status)) << r.describe();
  EXPECT_EQ(summary_string(*s, "reason"), h5->outcome().reason) << r.describe();
}

TEST(CliOutputSafety, DiskFullAfterTheSolveFailsBothRecords) {
  const std::string dir = fresh_test_dir();
  SmallDisk disk(dir + "/tiny", 2048);
  if (!disk.mounted()) GTEST_SKIP() << disk.why();
  // the solve's results fit; the frames and plots that follow do not, at each of these fills
  for (const int fill_kib : {0, 300, 600, 900}) {
    SCOPED_TRACE("filled " + std::to_string(fill_kib) + " KiB");
    fs::remove_all(dir + "/tiny/out");
    fs::remove(dir + "/tiny/fill");
    {
      std::ofstream fill(dir + "/tiny/fill", std::ios::binary);
      fill << std::string(static_cast<std::size_t>(fill_kib) * 1024, 'x');
    }
    const ProcResult r = run_flexframe({"run", "hinged_roof_h635", "--out", dir + "/tiny/out", "--quiet"},
                                       dir + "/run" + std::to_string(fill_kib), "", 120);
    EXPECT_EQ(r.signal, 0) << r.describe();
    EXPECT_NE(r.exit_code, 0) << "the frames and plots do not fit in 2 MB\n" << r.describe();
    expect_one_outcome(dir + "/tiny/out", r);
  }
}

// Issue 48, item 11: a results file that cannot even be created (no room for its first block)
// once ended in SIGSEGV in HDF5's exit handler, with no summary.json and an unreadable file. It
// ends `failed` (exit 1) like a disk that fills later, and says so.
TEST(CliOutputSafety, ResultsFileThatCannotBeCreatedEndsFailedCleanly) {
  const std::string dir = fresh_test_dir();
  SmallDisk disk(dir + "/tiny", 2048);
  if (!disk.mounted()) GTEST_SKIP() << disk.why();
  {
    std::ofstream fill(dir + "/tiny/fill", std::ios::binary);
    fill << std::string(1400 * 1024, 'x');
  }
  // a 120 x 120 plate: its mesh does not fit in what is left after the folder's reserve
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", dir + "/tiny/o", "--quiet", "--set",
                                      "part[0].n1=120", "--set", "part[0].n2=120"},
                                     dir + "/run", "", 120);
  expect_disk_full_failure(r);
  EXPECT_NE(r.err.find("results"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace ff::cli::test
