#include "core/solve/nested_dissection.h"

#include <metis.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace ff {
namespace {

// The off-diagonal pattern of a + aᵀ as sorted adjacency lists (CSR: start, neighbours)
struct Adjacency {
  std::vector<int> start, neighbours;
  int degree(int i) const { return start[i + 1] - start[i]; }
  const int* begin(int i) const { return neighbours.data() + start[i]; }
};

Adjacency symmetric_adjacency(const Eigen::SparseMatrix<double>& a) {
  const int n = static_cast<int>(a.cols());
  Adjacency g;
  std::vector<int> count(n + 1, 0);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
      if (it.row() != j) ++count[it.row()], ++count[j];
  g.start.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) g.start[i + 1] = g.start[i] + count[i];
  g.neighbours.resize(g.start[n]);
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it)
      if (it.row() != j) {
        g.neighbours[fill[it.row()]++] = j;
        g.neighbours[fill[j]++] = static_cast<int>(it.row());
      }
  // a full matrix lists each pair twice: sort and drop the repeats, row by row
  std::vector<int> compact_start(n + 1, 0);
  int out = 0;
  for (int i = 0; i < n; ++i) {
    int* b = g.neighbours.data() + g.start[i];
    int* e = g.neighbours.data() + g.start[i + 1];
    std::sort(b, e);
    e = std::unique(b, e);
    compact_start[i] = out;
    for (int* p = b; p != e; ++p) g.neighbours[out++] = *p;
  }
  compact_start[n] = out;
  g.neighbours.resize(out);
  g.start = std::move(compact_start);
  return g;
}

// Two unknowns are one supervariable when their closed neighbourhoods (adjacency plus itself) are
// equal: hashed, then compared exactly within a hash bucket
int group_by_pattern(const Adjacency& g, std::vector<int>& group) {
  const int n = static_cast<int>(g.start.size()) - 1;
  group.assign(n, -1);
  std::vector<int> representative;  // first unknown of each group
  std::unordered_multimap<std::uint64_t, int> by_hash;
  auto closed_hash = [&](int i) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the sorted closed neighbourhood
    bool placed = false;
    auto mix = [&h](int v) {
      h ^= static_cast<std::uint64_t>(v);
      h *= 1099511628211ull;
    };
    for (const int* p = g.begin(i); p != g.begin(i) + g.degree(i); ++p) {
      if (!placed && *p > i) mix(i), placed = true;
      mix(*p);
    }
    if (!placed) mix(i);
    return h;
  };
  std::vector<int> closed_a, closed_b;
  auto closed = [&](int i, std::vector<int>& out) {
    out.assign(g.begin(i), g.begin(i) + g.degree(i));
    out.insert(std::upper_bound(out.begin(), out.end(), i), i);
  };
  auto same_closed_pattern = [&](int i, int k) {
    if (g.degree(i) != g.degree(k)) return false;
    closed(i, closed_a);
    closed(k, closed_b);
    return closed_a == closed_b;
  };
  for (int i = 0; i < n; ++i) {
    const std::uint64_t h = closed_hash(i);
    auto [lo, hi] = by_hash.equal_range(h);
    for (auto it = lo; it != hi; ++it)
      if (same_closed_pattern(i, representative[it->second])) {
        group[i] = it->second;
        break;
      }
    if (group[i] < 0) {
      group[i] = static_cast<int>(representative.size());
      by_hash.emplace(h, group[i]);
      representative.push_back(i);
    }
  }
  return static_cast<int>(representative.size());
}

}  // namespace

int supervariables(const Eigen::SparseMatrix<double>& a, std::vector<int>& group) {
  return group_by_pattern(symmetric_adjacency(a), group);
}

std::vector<int> nested_dissection_positions(const Eigen::SparseMatrix<double>& a) {
  const int n = static_cast<int>(a.cols());
  if (n == 0 || a.rows() != a.cols()) return {};
  const Adjacency g = symmetric_adjacency(a);
  std::vector<int> group;
  const int groups = group_by_pattern(g, group);

  // the quotient graph: one vertex per supervariable, weighted by its size
  std::vector<std::vector<int>> members(groups);
  for (int i = 0; i < n; ++i) members[group[i]].push_back(i);
  std::vector<idx_t> xadj(groups + 1, 0), adjncy, weight(groups);
  std::vector<int> seen(groups, -1);
  for (int s = 0; s < groups; ++s) {
    const int r = members[s].front();
    weight[s] = static_cast<idx_t>(members[s].size());
    for (const int* p = g.begin(r); p != g.begin(r) + g.degree(r); ++p) {
      const int t = group[*p];
      if (t != s && seen[t] != s) {
        seen[t] = s;
        adjncy.push_back(t);
      }
    }
    xadj[s + 1] = static_cast<idx_t>(adjncy.size());
  }

  std::vector<idx_t> order(groups), position_of_group(groups);
  if (groups == 1 || adjncy.empty()) {
    std::iota(position_of_group.begin(), position_of_group.end(), 0);  // nothing to dissect
  } else {
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t count = groups;
    if (METIS_NodeND(&count, xadj.data(), adjncy.data(), weight.data(), options, order.data(),
                     position_of_group.data()) != METIS_OK)
      return {};
  }
  // METIS: row k of the permuted matrix is row order[k] of the original, so the groups are
  // eliminated in the sequence order[0], order[1], ...; a group's unknowns consecutively
  std::vector<int> sequence(groups);
  for (int s = 0; s < groups; ++s) sequence[position_of_group[s]] = s;
  std::vector<int> position(n);
  int next = 0;
  for (int s : sequence)
    for (int i : members[s]) position[i] = next++;
  return position;
}

std::vector<int> partition_mesh_elements(const std::vector<std::array<int, 4>>& elements, int nodes, int parts) {
  const int count = static_cast<int>(elements.size());
  if (parts < 1 || parts > count) return {};
  if (parts == 1) return std::vector<int>(count, 0);
  std::vector<idx_t> eptr(count + 1, 0), eind;
  eind.reserve(4 * elements.size());
  for (int k = 0; k < count; ++k) {
    for (int c = 0; c < 4; ++c) {
      const int I = elements[k][c];
      if (std::find(eind.begin() + eptr[k], eind.end(), I) == eind.end()) eind.push_back(I);
    }
    eptr[k + 1] = static_cast<idx_t>(eind.size());
  }
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = 1;  // the same parts on every rank
  idx_t ne = count, nn = nodes, common = 2, nparts = parts, cut = 0;
  std::vector<idx_t> epart(count), npart(nodes);
  if (METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &common, &nparts, nullptr, options, &cut,
                         epart.data(), npart.data()) != METIS_OK)
    return {};
  return std::vector<int>(epart.begin(), epart.end());
}

}  // namespace ff
