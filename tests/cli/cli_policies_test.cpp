// `flexframe policies` (the shell paper's Tables 3-4 as a generated table): on a coarse, short
// double pendulum it writes policies.csv/.md/.png with one row per policy; the counters obey what
// each policy means (every iteration: NOU = NOI; frozen: a single update unless a step fell back).

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

TEST(CliPolicies, WritesTheTableAndCountersFollowThePolicies) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe({"policies", "double_pendulum_shells", "--until", "0.01", "--policies",
                                      "full,nni:3,frozen,lazy:0.3:1", "--set", "part[0].n1=4", "--set", "part[0].n2=4",
                                      "--set", "part[1].n1=4", "--set", "part[1].n2=4", "--out", out},
                                     dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* f : {"/policies.csv", "/policies.md", "/policies.png"}) { EXPECT_TRUE(fs::is_regular_file(out + f)) << f; }
  std::ifstream csv(out + "/policies.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "dt,policy,status,NOI,NOU,wall_s,fallback_steps");
  std::map<std::string, std::pair<double, double>> counts;  // policy -> NOI, NOU
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::string dt, policy, status, noi, nou;
    std::getline(ss, dt, ','), std::getline(ss, policy, ','), std::getline(ss, status, ',');
    std::getline(ss, noi, ','), std::getline(ss, nou, ',');
    EXPECT_EQ(status, "completed") << line;
    counts[policy] = {std::stod(noi), std::stod(nou)};
  }
  ASSERT_EQ(counts.size(), 4u);
  EXPECT_EQ(counts["full"].first, counts["full"].second);
  EXPECT_EQ(counts["frozen"].second, 1);
  EXPECT_LE(counts["nni:3"].second, counts["full"].second);
  EXPECT_NE(r.out.find("| 5e-4 | frozen |"), std::string::npos) << r.describe();
  EXPECT_NE(r.out.find("| 5e-4 | lazy, ratio 0.3, next step 1 |"), std::string::npos) << r.describe();
}

TEST(CliPolicies, RefusesAMalformedLazyPolicy) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_flexframe({"policies", "double_pendulum_shells", "--until", "0.01", "--policies",
                                      "lazy:0.3:0.1:2", "--out", dir + "/out"},
                                     dir + "/run");
  EXPECT_NE(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.err.find("'lazy:0.3:0.1:2' is not"), std::string::npos) << r.describe();
}

}  // namespace
}  // namespace ff::cli::test
