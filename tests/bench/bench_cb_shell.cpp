// CB shell cost (core/shell/cb_shell.md "Implementation notes (speed)"): one element's force and
// force + tangent on a curved, distorted, deformed element for every effect set; the same over an
// array of distinct curved elements evaluated in turn, as the assembly loops do (the element data
// then come from outside L1/L2, which a single hot element hides); ShellModel
// assembly per Newton iteration (force + tangent) and the sparse factorize + solve of that
// tangent for clamped square plates n×n, n = 16 ... 256; assembly with 1 and 2 element-loop threads.
//   build/tests/bench/bench_cb_shell [--benchmark_filter=element]   (element/... and elements/...)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/mesh/generators.h"
#include "core/shell/cb_shell.h"
#include "core/shell/cb_shell_inertia.h"
#include "core/shell/shell_model.h"
#include "core/solve/sparse_solver.h"
#include "tests/support/shell_fixtures.h"

#include "core/assembly/element_threads.h"

namespace {

using namespace ff::shell;
using ff::shell::testing::curved;
using ff::shell::testing::frame;
using ff::shell::testing::rot;

// the curved, skewed cylinder patch of the unit tests and a large-rotation deformed state of it
ElementPoses curved_reference() { return curved(); }
ElementPoses deformed(const ElementPoses& ref) { return ff::shell::testing::deformed(ref, 5); }

// range(0): 1 = 6 DoF (drilling), range(1): hr, range(2): ans
ShellOptions element_options(const benchmark::State& state) {
  ShellOptions o;
  o.drilling = state.range(0) != 0;
  o.hr = state.range(1) != 0;
  o.ans = state.range(2) != 0;
  o.drilling_factor = 0.1;
  return o;
}

std::string effects_label(const ShellOptions& o) {
  return std::string(o.drilling ? "6dof" : "5dof") + (o.hr ? " hr" : " nohr") + (o.ans ? " ans" : " noans");
}

void bm_element(benchmark::State& state, bool with_tangent) {
  const ElementPoses ref = curved_reference();
  const ShellOptions o = element_options(state);
  const CbShellElement el(ref, isotropic_section(2.0e5, 0.3, 0.05), o);
  const ElementPoses cur = deformed(ref);
  Vec24 F;
  Mat24 K;
  for (auto _ : state) {
    el.evaluate(cur, F, with_tangent ? &K : nullptr);
    benchmark::DoNotOptimize(F.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(effects_label(o));
}

// the inertia force (D4) of one element, as every Newton correction of a dynamics run evaluates it
// (with gravity, fused as in the multibody model); range(0) = 1: also the iteration-matrix blocks
void bm_inertia(benchmark::State& state) {
  const ElementPoses ref = curved_reference();
  const CbShellInertia el(ref, 0.05, 7810.0);
  const ElementPoses cur = deformed(ref);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1, 1);
  ElementRates v, a;
  for (int I = 0; I < 4; ++I)
    for (int k = 0; k < 6; ++k) v[I][k] = u(gen), a[I][k] = 100 * u(gen);
  const Vec3 g(0, 0, -9.81);
  Vec24 F;
  Mat24 M, C, K;
  InertiaJacobians jac;
  if (state.range(0)) jac = {&M, &C, &K};
  for (auto _ : state) {
    el.evaluate(cur, v, a, F, jac, &g);
    benchmark::DoNotOptimize(F.data());
    benchmark::ClobberMemory();
  }
}

// n distinct elements of a half cylinder (radius 0.3, length 1.2, as double_pendulum_shells), each
// heap-allocated like the assembly's, with its own large rotation and random deformation; one
// benchmark iteration evaluates all of them in order. range(0) = n, range(1..3) = drill, hr, ans.
struct ElementArray {
  std::vector<std::unique_ptr<CbShellElement>> elements;
  std::vector<ElementPoses> current;
  std::vector<Vec24> forces;
  std::vector<Mat24> tangents;
};

ElementArray element_array(int n, const ShellOptions& o) {
  const int n1 = 15, n2 = (n + n1 - 1) / n1;
  const double radius = 0.3, length = 1.2, pi = 3.14159265358979323846;
  auto node = [&](int i, int j) {
    const double phi = pi * (1.0 - static_cast<double>(i) / n1);
    const Vec3 nrm(std::cos(phi), 0.0, std::sin(phi));
    return NodePose{frame(nrm), radius * nrm + Vec3(0, length * j / n2, 0)};
  };
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-1, 1);
  ElementArray a;
  for (int k = 0; k < n; ++k) {
    const int i = k % n1, j = k / n1;
    const ElementPoses ref = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
    a.elements.push_back(std::make_unique<CbShellElement>(ref, isotropic_section(1.0e9, 0.3, 0.01), o));
    const Mat3 Q = rot(Vec3(u(g), u(g), u(g)));
    ElementPoses cur = ref;
    for (auto& p : cur) {
      p.p = Q * p.p + Vec3(0.1, -0.2, 0.3) + 0.002 * Vec3(u(g), u(g), u(g));
      p.R = Q * p.R * rot(0.02 * Vec3(u(g), u(g), u(g)));
    }
    a.current.push_back(cur);
  }
  a.forces.resize(n);
  a.tangents.resize(n);
  return a;
}

void bm_elements(benchmark::State& state, bool with_tangent) {
  ShellOptions o;
  o.drilling = state.range(1) != 0;
  o.hr = state.range(2) != 0;
  o.ans = state.range(3) != 0;
  const int n = static_cast<int>(state.range(0));
  ElementArray a = element_array(n, o);
  for (auto _ : state) {
    for (int k = 0; k < n; ++k)
      a.elements[k]->evaluate(a.current[k], a.forces[k], with_tangent ? &a.tangents[k] : nullptr);
    benchmark::ClobberMemory();
  }
  state.SetLabel(effects_label(o));
  // CPU time per element (the figure to compare with the single-element rows)
  state.counters["per_element"] = benchmark::Counter(
      static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["bytes_per_element"] = static_cast<double>(sizeof(CbShellElement));
}

// n×n plate 1×1 in z = 0, clamped at x = 0, transverse load on the edge x = 1; the state is one
// Newton update away from the reference so every element is deformed
struct PlateProblem {
  std::unique_ptr<ShellModel> model;
  Eigen::VectorXd residual;
  ff::SparseMatrixD tangent;
};

PlateProblem& plate(int n) {
  static std::map<int, PlateProblem> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  ShellModelSpec spec;
  spec.mesh = ff::mesh::rectangular_plate(1.0, 1.0, n, n);
  spec.section = isotropic_section(1.0e7, 0.3, 0.01);
  for (int I = 0; I < spec.mesh.node_count(); ++I) {
    const Vec3& p = spec.mesh.points[I];
    if (p.x() < 1e-12) spec.restraints.emplace_back(I, kClamped);
    if (p.x() > 1.0 - 1e-12) spec.loads.push_back({I, Vec3(0, 0, -1.0 / (n + 1)), Vec3::Zero(), false});
  }
  PlateProblem& pp = cache[n];
  pp.model = std::make_unique<ShellModel>(std::move(spec));
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::VectorXd delta(pp.model->size());
  for (int k = 0; k < delta.size(); ++k) delta[k] = u(g);
  pp.model->update(delta);
  pp.model->evaluate(1.0, pp.residual, &pp.tangent, nullptr);
  return pp;
}

// range(0) = n, range(1) = element-loop threads
void bm_assembly(benchmark::State& state) {
  PlateProblem& pp = plate(static_cast<int>(state.range(0)));
  pp.model->set_threads({static_cast<int>(state.range(1)), nullptr});
  for (auto _ : state) {
    pp.model->evaluate(1.0, pp.residual, &pp.tangent, nullptr);
    benchmark::DoNotOptimize(pp.tangent.valuePtr());
  }
  pp.model->set_threads({1, nullptr});
  state.counters["dofs"] = pp.model->size();
  state.counters["elements"] = static_cast<double>(state.range(0) * state.range(0));
}

// numeric factorization + one solve with the default backend (pattern analyzed once, as the
// static solvers do)
void bm_solve(benchmark::State& state) {
  PlateProblem& pp = plate(static_cast<int>(state.range(0)));
  ff::SparseLinearSolver solver;
  if (!solver.analyze(pp.tangent)) state.SkipWithError("analyze failed");
  Eigen::VectorXd x;
  for (auto _ : state) {
    const ff::LinearStatus s = solver.factorize(pp.tangent);
    if (!s) state.SkipWithError(s.message.c_str());
    if (!solver.solve(pp.residual, x)) state.SkipWithError("solve failed");
    benchmark::DoNotOptimize(x.data());
  }
  state.SetLabel(std::string(ff::to_string(solver.backend())));
  state.counters["dofs"] = pp.model->size();
  state.counters["nnz"] = static_cast<double>(pp.tangent.nonZeros());
}

}  // namespace

int main(int argc, char** argv) {
  // the machine is shared: repetitions and their minimum, except the one-shot 256×256 solve
  auto min = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
  for (bool tangent : {false, true}) {
    auto* b = benchmark::RegisterBenchmark(tangent ? "element/force_tangent" : "element/force", bm_element, tangent);
    for (int drilling : {0, 1})
      for (int hr : {1, 0})
        for (int ans : {1, 0}) b->Args({drilling, hr, ans});
    b->ArgNames({"drill", "hr", "ans"})->Unit(benchmark::kMicrosecond)->Repetitions(5);
    b->ComputeStatistics("min", min)->ReportAggregatesOnly(true);
  }
  benchmark::RegisterBenchmark("inertia", bm_inertia)
      ->Arg(0)
      ->Arg(1)
      ->ArgName("jacobians")
      ->Unit(benchmark::kMicrosecond)
      ->Repetitions(5)
      ->ComputeStatistics("min", min)
      ->ReportAggregatesOnly(true);
  for (bool tangent : {false, true}) {
    auto* b = benchmark::RegisterBenchmark(tangent ? "elements/force_tangent" : "elements/force", bm_elements, tangent);
    for (int n : {450, 1800}) b->Args({n, 0, 1, 1});
    for (int drilling : {0, 1})
      for (int hr : {1, 0})
        for (int ans : {1, 0})
          if (drilling || !hr || !ans) b->Args({450, drilling, hr, ans});
    b->ArgNames({"n", "drill", "hr", "ans"})->Unit(benchmark::kMillisecond)->Repetitions(5);
    b->ComputeStatistics("min", min)->ReportAggregatesOnly(true);
  }
  for (int n : {16, 32, 64, 128, 256}) {
    auto* a = benchmark::RegisterBenchmark("assembly", bm_assembly)->Args({n, 1})->Args({n, 2});
    a->ArgNames({"n", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
    a->Repetitions(3)->ComputeStatistics("min", min)->ReportAggregatesOnly(true);
  }
  for (int n : {16, 32, 64, 128, 256}) {
    auto* s = benchmark::RegisterBenchmark("factorize_solve", bm_solve)->Arg(n)->ArgName("n");
    s->Unit(benchmark::kMillisecond)->UseRealTime();
    if (n < 256) s->Repetitions(3)->ComputeStatistics("min", min)->ReportAggregatesOnly(true);
    else s->Iterations(1);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
