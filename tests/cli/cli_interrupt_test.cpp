// Ctrl-C keeps everything: a long run interrupted with SIGINT exits 130 (normally, not killed by
// the signal) with summary.json "interrupted" and a results.h5 holding every frame up to the stop.

#include <gtest/gtest.h>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

TEST(CliInterrupt, SigintKeepsResultsAndSummary) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  // 60 s of simulated time at dt = 2 ms: far longer than the test waits
  Child child({"run", "hub_beam_converged_tau1", "--out", out, "--no-plots", "--frame-every", "1000000", "--set",
               "solver.end=60"},
              dir + "/run");
  ASSERT_TRUE(child.started());
  const auto t0 = std::chrono::steady_clock::now();
  const auto waited = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  while (!fs::exists(out + "/results.h5") && child.running() && waited() < 30)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(out + "/results.h5")) << child.wait(1).describe();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ASSERT_TRUE(child.running()) << "the run ended before it was interrupted\n" << child.wait(1).describe();
  ASSERT_TRUE(child.send(SIGINT));
  const ProcResult r = child.wait(30);
  ASSERT_FALSE(r.timed_out) << "no exit within 30 s of SIGINT\n" << r.describe();
  ASSERT_EQ(r.signal, 0) << "killed by the signal instead of stopping cleanly\n" << r.describe();
  EXPECT_EQ(r.exit_code, 130) << r.describe();

  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err << "\n" << r.describe();
  expect_summary_shape(*s);
  EXPECT_EQ(summary_string(*s, "status"), "interrupted");
  const double stop = summary_number(*s, "stop_time");
  EXPECT_GT(stop, 0.0);
  EXPECT_LT(stop, 60.0);
  // the reason says when: "... at t = 1.948 s"
  const std::string reason = summary_string(*s, "reason");
  EXPECT_NE(reason.find("interrupted"), std::string::npos) << reason;
  EXPECT_NE(reason.find("t = "), std::string::npos) << reason;
  std::ostringstream when;
  when << stop;  // %g-like, as the app prints it
  EXPECT_NE(reason.find(when.str()), std::string::npos) << "reason '" << reason << "' does not name t = " << stop;
  // the one frame the interval allows (frame 0), and the state where it stopped: the final state
  // is always a frame
  EXPECT_TRUE(fs::is_regular_file(out + "/frames/frame_00000.png"));
  EXPECT_TRUE(fs::is_regular_file(out + "/frames/frame_00001.png"));
  EXPECT_FALSE(fs::exists(out + "/frames/frame_00002.png"));

  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  ASSERT_GT(h5->frame_count(), 0u);
  const RunOutcome o = h5->outcome();
  EXPECT_EQ(o.status, RunStatus::interrupted) << o.reason;
  EXPECT_NEAR(o.stop_time, stop, 1e-9);
  const std::vector<double> t = h5->times();
  ASSERT_EQ(t.size(), h5->frame_count());
  for (std::size_t i = 1; i < t.size(); ++i) { ASSERT_GT(t[i], t[i - 1]) << "frame " << i; }
  EXPECT_NEAR(t.back(), stop, 1e-9) << "frames after the last flush were lost";
  EXPECT_NEAR(h5->frame(t.size() - 1).time, stop, 1e-9);
  EXPECT_EQ(static_cast<double>(t.size() - 1), summary_number(*s, "steps"));
}

}  // namespace
}  // namespace ff::cli::test
