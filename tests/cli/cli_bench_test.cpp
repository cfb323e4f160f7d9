// `flexframe bench --solve --json FILE`: the file carries the element block and one row per plate
// with the keys docs/performance.md reads (not the timings' values: those are benchmarks, not
// tests), and the counted flops are the element's, so they match count_element_flops.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "core/shell/cb_shell.h"
#include "core/shell/sample_elements.h"

namespace ff::cli::test {
namespace {

TEST(CliBench, SolveWritesTheElementBlockAndThePlateRows) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/bench.json";
  const ProcResult r = run_flexframe({"bench", "--solve", "--max-n", "16", "--repeat", "1", "--json", json}, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json j = nlohmann::json::parse(read_text(json));

  const nlohmann::json& e = j.at("element");
  for (const char* key : {"force_us", "force_tangent_us", "same_flop_product_us"}) EXPECT_GT(e.at(key).get<double>(), 0.0) << key;
  // the bench's element: the curved, deformed sample with 5 DoF, hr and ans
  shell::ShellOptions o;
  o.hr = o.ans = true;
  const shell::ElementPoses ref = shell::samples::curved();
  const shell::ElementFlops flops =
      shell::count_element_flops(shell::CbShellElement(ref, {2.0e5, 0.3, 0.05, 5.0 / 6.0}, o), shell::samples::deformed(ref, 5));
  EXPECT_EQ(e.at("force_flops").get<long long>(), flops.force);
  EXPECT_EQ(e.at("force_tangent_flops").get<long long>(), flops.force_tangent);

  const nlohmann::json& plates = j.at("plate");
  ASSERT_EQ(plates.size(), 1u);  // --max-n 16
  const nlohmann::json& p = plates.at(0);
  EXPECT_EQ(p.at("n").get<int>(), 16);
  EXPECT_EQ(p.at("dofs").get<int>(), 1360);  // 17 x 17 nodes x 5, minus the clamped edge's 17 x 5
  EXPECT_GT(p.at("assembly_ms").get<double>(), 0.0);
  EXPECT_GT(p.at("factorize_solve_ms").get<double>(), 0.0);
  EXPECT_FALSE(p.at("backend").get<std::string>().empty());
  // which BLAS kernels the factorizations ran on ("OpenBLAS, Haswell kernels", or "not OpenBLAS")
  EXPECT_NE(j.at("blas").get<std::string>().find("BLAS"), std::string::npos) << j.at("blas");
}

}  // namespace
}  // namespace ff::cli::test
