// Issue 48, items 8 and 9: no output of any verb follows a link it did not make.
// Each test runs a job once to learn every path it writes (the folder's manifest, plus the
// bookkeeping files and temporaries beside them), then, for each of those paths in a fresh folder,
// plants a symbolic link there to a victim outside the folder and runs the job again. The victim
// must be untouched (a file keeps its bytes, a folder its listing), the planted link must stay,
// and the job must say it refused ("symbolic link") with a non-zero exit, never report success.
// A hard link to an outside file is planted at results.h5 too. Before the fix, results.h5,
// summary.json.tmp, frames/, a frame, plots/ and .flexframe-files.tmp were written through.

#include <gtest/gtest.h>
#include <unistd.h>

#include <functional>
#include <set>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

constexpr const char* kPrecious = "a user's file, outside the output folder\n";

// every path the job at `out` wrote (from its manifest), folders with a trailing '/', and the
// files a job makes beside them that the manifest does not list
std::vector<std::string> written_paths(const std::string& out) {
  std::set<std::string> paths;
  std::istringstream manifest(read_text(out + "/.flexframe-files"));
  for (std::string line; std::getline(manifest, line);)
    if (!line.empty()) paths.insert(line);
  EXPECT_FALSE(paths.empty()) << "no manifest in " << out;
  for (const char* own : {".flexframe-files", ".flexframe-files.tmp", ".flexframe.lock", ".flexframe-reserve"})
    paths.insert(own);
  for (const std::string& p : std::vector<std::string>(paths.begin(), paths.end()))
    if (p.size() > 5 && (p.substr(p.size() - 5) == ".json" || p.substr(p.size() - 3) == ".md" ||
                         p.substr(p.size() - 4) == ".csv"))
      paths.insert(p + ".tmp");  // written through a temporary renamed over it
  return {paths.begin(), paths.end()};
}

// the listing of `dir` with each file's bytes, to tell whether anything in it changed
std::vector<std::string> snapshot(const std::string& dir) {
  std::vector<std::string> s;
  for (const std::string& rel : tree(dir)) s.push_back(rel + "=" + read_text(dir + "/" + rel));
  return s;
}

/// Plants a link at each path the job `args(out)` writes and runs it again: see the file comment.
void expect_no_write_through_links(const std::string& dir,
                                   const std::function<std::vector<std::string>(const std::string&)>& args) {
  fs::create_directories(dir);
  const std::string first = dir + "/first";
  const ProcResult r = run_flexframe(args(first), dir + "/first", "", 120);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::vector<std::string> paths = written_paths(first);
  int k = 0;
  for (const std::string& entry : paths) {
    SCOPED_TRACE("link planted at " + entry);
    const bool folder = entry.back() == '/';
    const std::string rel = folder ? entry.substr(0, entry.size() - 1) : entry;
    const std::string out = dir + "/case" + std::to_string(k), victim = dir + "/victim" + std::to_string(k);
    ++k;
    fs::create_directories(fs::path(out + "/" + rel).parent_path());
    if (folder) {
      // a folder that holds what the job would write inside it, and one more file
      fs::create_directories(victim);
      write_text(victim + "/keep.txt", kPrecious);
      for (const std::string& p : paths)
        if (p.rfind(entry, 0) == 0 && p.size() > entry.size() && p.back() != '/' &&
            p.find('/', entry.size()) == std::string::npos)
          write_text(victim + "/" + p.substr(entry.size()), kPrecious);
    } else {
      write_text(victim, kPrecious);
    }
    const std::vector<std::string> before = folder ? snapshot(victim) : std::vector<std::string>{read_text(victim)};
    fs::remove_all(out + "/" + rel);
    fs::create_symlink(victim, out + "/" + rel);
    const ProcResult again = run_flexframe(args(out), out, "", 120);
    const std::vector<std::string> after = folder ? snapshot(victim) : std::vector<std::string>{read_text(victim)};
    EXPECT_EQ(after, before) << "the job wrote through the link at " << entry << "\n" << again.describe();
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(out + "/" + rel))) << "the planted link was removed or replaced";
    EXPECT_NE(again.exit_code, 0) << "the job reported success with a link in its way\n" << again.describe();
    EXPECT_EQ(again.signal, 0) << again.describe();
    EXPECT_NE(again.err.find("symbolic link"), std::string::npos) << "the refusal does not say why\n"
                                                                  << again.describe();
  }
}

TEST(CliOutputLinks, RunWritesThroughNoPlantedLink) {
  const std::string dir = fresh_test_dir();
  expect_no_write_through_links(dir, [](const std::string& out) {
    return std::vector<std::string>{"run", "clamped_plate_pressure", "--out", out, "--quiet", "--export", "vtu,obj"};
  });
}

TEST(CliOutputLinks, ReplayAndCompareWriteThroughNoPlantedLink) {
  const std::string dir = fresh_test_dir();
  const std::string run = dir + "/run";
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", run, "--quiet", "--no-frames"}, run);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  expect_no_write_through_links(dir + "/replay", [&](const std::string& out) {
    return std::vector<std::string>{"replay", run, "--out", out, "--export", "vtu"};
  });
  expect_no_write_through_links(dir + "/compare", [&](const std::string& out) {
    return std::vector<std::string>{"compare", run, run, "--out", out};
  });
}

TEST(CliOutputLinks, StudyWritesThroughNoPlantedLink) {
  const std::string dir = fresh_test_dir();
  const std::string study = dir + "/s.toml";
  write_text(study, "[study]\nscene = \"hub_beam_converged_tau1\"\nmetric = \"tip_transverse_at_2s_m\"\n"
                    "set = [\"solver.end=2\"]\n\n[[vary]]\nkey = [\"solver.dt\"]\nvalues = [\"0.004\", \"0.008\"]\n\n"
                    "[reference]\nkind = \"finest\"\n");
  expect_no_write_through_links(dir, [&](const std::string& out) {
    return std::vector<std::string>{"study", study, "--out", out, "--jobs", "1"};
  });
}

// A hard link is one file under two names: truncating results.h5 would empty the user's file.
TEST(CliOutputLinks, HardLinkAtResultsIsNotTruncated) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out", victim = dir + "/victim.h5";
  fs::create_directories(out);
  write_text(victim, kPrecious);
  ASSERT_EQ(::link(victim.c_str(), (out + "/results.h5").c_str()), 0) << std::strerror(errno);
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure", "--out", out, "--quiet"}, dir + "/run");
  EXPECT_EQ(read_text(victim), kPrecious) << r.describe();
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_NE(r.err.find("hard link"), std::string::npos) << r.describe();
}

// The single files a user names outside any output folder (`bench --json`; the window's screenshot
// and saved scene use the same opener) are opened like every output: a link planted at the name
// is refused, its target keeps its bytes, and the bench says it could not write.
TEST(CliOutputLinks, BenchJsonIsNotWrittenThroughAPlantedLink) {
  const std::string dir = fresh_test_dir();
  const std::string victim = dir + "/victim.json", json = dir + "/bench.json";
  write_text(victim, kPrecious);
  fs::create_symlink(victim, json);
  const ProcResult r = run_flexframe({"bench", "--estimate", "2000", "--json", json}, dir + "/run");
  EXPECT_EQ(read_text(victim), kPrecious) << r.describe();
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(json))) << "the planted link was removed or replaced";
  EXPECT_NE(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.err.find("symbolic link"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace ff::cli::test
