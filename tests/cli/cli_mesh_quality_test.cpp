// The mesh quality report (issue 32, item 5; core/mesh/mesh_quality.md): `check` prints it for a
// shell scene, a [mesh_quality] limit (in the file or by --set) changes which quads are warned
// about, a bad limit is refused at its line, `run` warns on stderr and summary.json carries it.
#include "tests/cli/cli_support.h"

namespace ff::cli::test {
namespace {

const char* kPlate = "clamped_plate_pressure";  // 8 x 8 square quads of a unit plate

// the bundled plate with n2 = 2: 16 quads 1/8 x 1/2, aspect ratio 4 each
std::string elongated_plate(const std::string& dir, const std::string& extra) {
  const std::string path = dir + "/plate.toml";
  std::string text = read_text(scene_path(kPlate));
  const std::string from = "n2 = 8";
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos);
  text.replace(at, from.size(), "n2 = 2");
  write_text(path, text + extra);
  return path;
}

TEST(CliMeshQuality, CheckPrintsTheReport) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_flexframe({"check", kPlate}, dir + "/check");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("mesh quality: 64 quads, 81 nodes; none past the limits"), std::string::npos) << r.out;
  for (const char* line : {"  aspect ratio   worst 1 at quad ", "  skew           worst 0.0 deg at quad ",
                           "  warping        worst 0.0 deg at quad ", "  Jacobian ratio worst 1.000 at quad "})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
  // a model without a shell mesh has no report
  const ProcResult hub = run_flexframe({"check", "hub_beam_efg_tau1"}, dir + "/hub");
  ASSERT_EQ(hub.exit_code, 0) << hub.describe();
  EXPECT_EQ(hub.out.find("mesh quality"), std::string::npos) << hub.out;
}

TEST(CliMeshQuality, ALimitChangesWhatIsWarned) {
  const std::string dir = fresh_test_dir();
  // aspect ratio 4 is within the default limit 10
  const ProcResult plain = run_flexframe({"check", elongated_plate(dir, "")}, dir + "/plain");
  ASSERT_EQ(plain.exit_code, 0) << plain.describe();
  EXPECT_NE(plain.out.find("aspect ratio   worst 4 at quad 0, typical 4, limit 10: 0 past it"), std::string::npos)
      << plain.out;
  EXPECT_EQ(plain.out.find("warning"), std::string::npos) << plain.out;
  // the same mesh against mesh_quality.max_aspect_ratio = 3 in the file: every quad is named
  const ProcResult strict =
      run_flexframe({"check", elongated_plate(dir, "\n[mesh_quality]\nmax_aspect_ratio = 3\n")}, dir + "/strict");
  ASSERT_EQ(strict.exit_code, 0) << strict.describe();  // a warning, not a refusal
  EXPECT_NE(strict.out.find("warning: 16 quads have an aspect ratio above mesh_quality.max_aspect_ratio = 3: "
                            "quad 0 = 4, quad 1 = 4, quad 2 = 4, quad 3 = 4, quad 4 = 4, and 11 more"),
            std::string::npos)
      << strict.out;
  // the same limit by --set
  const ProcResult set =
      run_flexframe({"check", elongated_plate(dir, ""), "--set", "mesh_quality.max_aspect_ratio=3"}, dir + "/set");
  ASSERT_EQ(set.exit_code, 0) << set.describe();
  EXPECT_NE(set.out.find("warning: 16 quads have an aspect ratio above mesh_quality.max_aspect_ratio = 3"),
            std::string::npos)
      << set.out;
  // limits on the other metrics, however tight, leave rectangles alone (0 skew, 0 warping)
  const ProcResult skew = run_flexframe({"check", elongated_plate(dir, ""), "--set", "mesh_quality.max_skew=1e-6",
                                         "--set", "mesh_quality.max_warping=1e-6"},
                                        dir + "/skew");
  ASSERT_EQ(skew.exit_code, 0) << skew.describe();
  EXPECT_EQ(skew.out.find("warning"), std::string::npos) << skew.out;
}

TEST(CliMeshQuality, ABadLimitIsRefusedAtItsLine) {
  const std::string dir = fresh_test_dir();
  const std::string path = elongated_plate(dir, "\n[mesh_quality]\nmax_skew = 95.0\n");
  const ProcResult r = run_flexframe({"check", path}, dir + "/check");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  const std::string text = read_text(path);
  const auto lines = std::count(text.begin(), text.end(), '\n');  // the limit is on the last line
  EXPECT_NE(r.err.find("plate.toml:" + std::to_string(lines) + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("key 'mesh_quality.max_skew'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(0, 90]"), std::string::npos) << r.err;
}

TEST(CliMeshQuality, RunWarnsAndTheSummaryCarriesIt) {
  const std::string dir = fresh_test_dir();
  const std::string path = elongated_plate(dir, "\n[mesh_quality]\nmax_aspect_ratio = 3\n");
  const ProcResult r =
      run_flexframe({"run", path, "--out", dir + "/out", "--no-frames", "--no-plots", "--quiet"}, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.err.find("warning: mesh quality: 16 quads have an aspect ratio above mesh_quality.max_aspect_ratio = 3"),
            std::string::npos)
      << r.err;
  std::string err;
  const std::optional<Json> s = read_summary(dir + "/out", &err);
  ASSERT_TRUE(s) << err;
  const Json* q = s->get("mesh_quality");
  ASSERT_TRUE(q && q->kind == Json::Kind::object) << "summary.json has no mesh_quality object";
  EXPECT_EQ(q->get("quads")->number, 16);
  EXPECT_EQ(q->get("nodes")->number, 27);
  EXPECT_EQ(q->get("poor_quads")->number, 16);
  const Json* aspect = q->get("metrics")->get("aspect_ratio");
  ASSERT_TRUE(aspect);
  EXPECT_NEAR(aspect->get("worst")->number, 4.0, 1e-12);
  EXPECT_EQ(aspect->get("worst_quad")->number, 0);
  EXPECT_EQ(aspect->get("worst_element")->string, "quad 0");
  EXPECT_NEAR(aspect->get("typical")->number, 4.0, 1e-12);
  EXPECT_EQ(aspect->get("limit")->number, 3);
  EXPECT_EQ(aspect->get("past_limit")->number, 16);
  EXPECT_EQ(aspect->get("past_limit_quads")->array.size(), 16u);
  const Json* jacobian = q->get("metrics")->get("jacobian_ratio");
  ASSERT_TRUE(jacobian);
  EXPECT_NEAR(jacobian->get("worst")->number, 1.0, 1e-12);
  EXPECT_EQ(jacobian->get("past_limit")->number, 0);
  ASSERT_EQ(q->get("warnings")->array.size(), 1u);
  EXPECT_EQ(q->get("warnings")->array[0].string.rfind("16 quads have an aspect ratio", 0), 0u);
}

}  // namespace
}  // namespace ff::cli::test
