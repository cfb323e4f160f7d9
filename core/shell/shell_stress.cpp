#include "core/shell/shell_stress.h"

#include <algorithm>
#include <cmath>

namespace ff::shell {

double von_mises(const Vec5& s) {  // laminate.md (L11)
  return std::sqrt(std::max(0.0, s[0] * s[0] - s[0] * s[1] + s[1] * s[1] + 3.0 * (s[2] * s[2] + s[3] * s[3] + s[4] * s[4])));
}

std::array<double, 2> principal_stresses(const Vec5& s) {
  const double mean = 0.5 * (s[0] + s[1]), radius = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  return {mean + radius, mean - radius};
}

StressLayout stress_layout(const ShellElements& elements) {
  StressLayout layout;
  for (const ShellElement& e : elements.all()) {
    const ShellSection& s = e.elastic->section();
    if (!s.plies) continue;
    layout.max_plies = std::max(layout.max_plies, static_cast<int>(s.plies->size()));
    for (const Ply& p : *s.plies)
      if (p.strength[0] > 0) layout.failure_index = true;
  }
  return layout;
}

std::vector<StressField> stress_fields(const StressLayout& layout) {
  std::vector<StressField> f;
  const char* where[3] = {"bottom", "mid", "top"};
  const char* surface[3] = {"bottom surface (the director's negative side)", "reference surface", "top surface"};
  f.push_back({"von_mises", "von Mises stress, the largest over the section's stations (laminate.md L11)"});
  for (int s : {0, 2}) f.push_back({std::string("von_mises_") + where[s], std::string("von Mises stress at the ") + surface[s]});
  for (int s : {0, 2}) {
    f.push_back({std::string("principal1_") + where[s], std::string("larger in-plane principal stress at the ") + surface[s]});
    f.push_back({std::string("principal2_") + where[s], std::string("smaller in-plane principal stress at the ") + surface[s]});
  }
  for (int s = 0; s < 3; ++s)
    for (const char* c : {"11", "22", "12"})
      f.push_back({std::string("sigma") + c + "_" + where[s],
                   std::string("stress s") + c + " at the " + surface[s] + " (section axes: x1 the reference direction)"});
  for (const char* c : {"11", "22", "12"}) f.push_back({std::string("N") + c, std::string("membrane resultant N") + c + " per unit length"});
  for (const char* c : {"11", "22", "12"}) f.push_back({std::string("M") + c, std::string("bending resultant M") + c + " per unit length"});
  for (const char* c : {"1", "2"}) f.push_back({std::string("Q") + c, std::string("transverse shear resultant Q") + c + " per unit length"});
  if (layout.max_plies > 0) {
    if (layout.failure_index) f.push_back({"tsai_wu", "Tsai-Wu failure index, the largest over every ply (laminate.md L12)"});
    for (int k = 1; k <= layout.max_plies; ++k) {
      const std::string p = "ply" + std::to_string(k);
      const std::string at = " at the middle of ply " + std::to_string(k) + " (from the bottom), fibre axes";
      f.push_back({p + "_sigma1", "stress along the fibre" + at});
      f.push_back({p + "_sigma2", "stress across the fibre" + at});
      f.push_back({p + "_tau12", "in-plane shear stress" + at});
      if (layout.failure_index) f.push_back({p + "_tsai_wu", "Tsai-Wu index of ply " + std::to_string(k) + ", the largest over its stations"});
    }
  }
  return f;
}

namespace {
// one element's values in the order of stress_fields; false where the element has no such ply
void element_values(const ElementStress& s, const StressLayout& layout, std::vector<double>& v, std::vector<char>& has) {
  std::size_t i = 0;
  auto put = [&](double x, bool present = true) { v[i] = x, has[i] = present, ++i; };
  double vm = std::max({von_mises(s.surface[0]), von_mises(s.surface[1]), von_mises(s.surface[2])});
  for (int k = 0; k < s.plies; ++k)
    for (const Vec5& station : s.ply[k]) vm = std::max(vm, von_mises(station));
  put(vm);
  for (int w : {0, 2}) put(von_mises(s.surface[w]));
  for (int w : {0, 2}) {
    const std::array<double, 2> p = principal_stresses(s.surface[w]);
    put(p[0]), put(p[1]);
  }
  for (int w = 0; w < 3; ++w)
    for (int c = 0; c < 3; ++c) put(s.surface[w][c]);
  for (int c = 0; c < 3; ++c) put(s.N[c]);
  for (int c = 0; c < 3; ++c) put(s.M[c]);
  for (int c = 0; c < 2; ++c) put(s.Q[c]);
  if (layout.max_plies == 0) return;
  if (layout.failure_index) {
    double worst = 0;
    bool any = false;
    for (int k = 0; k < s.plies; ++k)
      if (std::isfinite(s.tsai_wu[k])) worst = any ? std::max(worst, s.tsai_wu[k]) : s.tsai_wu[k], any = true;
    put(worst, any);
  }
  for (int k = 0; k < layout.max_plies; ++k) {
    const bool present = k < s.plies;
    for (int c = 0; c < 3; ++c) put(present ? s.ply[k][1][c] : 0.0, present);
    if (layout.failure_index) put(present && std::isfinite(s.tsai_wu[k]) ? s.tsai_wu[k] : 0.0, present && std::isfinite(s.tsai_wu[k]));
  }
}
}  // namespace

std::vector<std::vector<double>> nodal_stress_fields(const ShellElements& elements, const StressLayout& layout,
                                                     const std::vector<NodePose>& X_WN) {
  const std::size_t nf = stress_fields(layout).size(), nn = X_WN.size();
  std::vector<std::vector<double>> sum(nf, std::vector<double>(nn, 0.0));
  std::vector<std::vector<int>> count(nf, std::vector<int>(nn, 0));
  std::vector<double> v(nf);
  std::vector<char> has(nf);
  ElementStress s;
  ElementPoses cur;
  for (const ShellElement& e : elements.all()) {
    ShellElements::corner_poses(e, X_WN, cur);
    for (int c = 0; c < 4; ++c) {
      e.elastic->stresses(cur, s, c);
      element_values(s, layout, v, has);
      for (std::size_t f = 0; f < nf; ++f)
        if (has[f]) sum[f][e.nodes[c]] += v[f], ++count[f][e.nodes[c]];
    }
  }
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t n = 0; n < nn; ++n)
      if (count[f][n]) sum[f][n] /= count[f][n];
  return sum;
}

double nodal_stress_value(const ShellElements& elements, const StressLayout& layout, std::size_t field, int node,
                          const std::vector<NodePose>& X_WN) {
  const std::size_t nf = stress_fields(layout).size();
  std::vector<double> v(nf);
  std::vector<char> has(nf);
  ElementStress s;
  ElementPoses cur;
  double sum = 0.0;
  int count = 0;
  // in element order, each element once per corner at the node, as nodal_stress_fields sums (the
  // mean over the adjacent elements that have the field, 0 when none has): the same value bit for bit
  for (const ShellElement& e : elements.all()) {
    const int corners = static_cast<int>(std::count(e.nodes.begin(), e.nodes.end(), node));
    if (corners == 0) continue;
    ShellElements::corner_poses(e, X_WN, cur);
    e.elastic->stresses(cur, s);
    element_values(s, layout, v, has);
    if (has[field])
      for (int c = 0; c < corners; ++c) sum += v[field], ++count;
  }
  return count ? sum / count : 0.0;
}

}  // namespace ff::shell
