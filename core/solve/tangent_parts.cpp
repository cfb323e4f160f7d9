#include "core/solve/tangent_parts.h"

#include "core/solve/nested_dissection.h"

#include <algorithm>
#include <limits>

namespace ff {

namespace {
constexpr int kNone = std::numeric_limits<int>::max();
}

ElementShare::ElementShare(const std::vector<std::array<int, 4>>& elements, int nodes, int rank, int ranks)
    : rank_(rank), ranks_(ranks), elements_(static_cast<int>(elements.size())) {
  if (ranks_ < 2) {
    mine_.resize(elements_);
    for (int k = 0; k < elements_; ++k) mine_[k] = k;
    return;
  }
  rank_of_ = partition_mesh_elements(elements, nodes, ranks_);
  if (rank_of_.empty()) {  // fewer elements than ranks, or METIS failed: index ranges
    const int count = static_cast<int>(elements.size());
    rank_of_.resize(count);
    for (int r = 0; r < ranks_; ++r) {
      const RankShare s = rank_share(count, r, ranks_);
      for (int k = s.begin; k < s.end; ++k) rank_of_[k] = r;
    }
  }
  for (int k = 0; k < static_cast<int>(rank_of_.size()); ++k)
    if (rank_of_[k] == rank_) mine_.push_back(k);
}

TangentParts::TangentParts(int nonzeros, int nodes, const ElementShare& share)
    : me_(share.rank()),
      share_(&share),
      lowest_(nonzeros, kNone),
      highest_(nonzeros, -1),
      node_rank_(nodes, kNone),
      owns_node_(nodes, 0) {}

void TangentParts::touch(int position, int rank) {
  lowest_[position] = std::min(lowest_[position], rank);
  highest_[position] = std::max(highest_[position], rank);
}

// distributed.md (D1): element k is added by the rank whose share holds it
void TangentParts::add_element(int k, const int* positions, int count, const int* nodes, int node_count) {
  const int rank = share_->rank_of(k);
  for (int q = 0; q < count; ++q)
    if (positions[q] >= 0) touch(positions[q], rank);
  for (int c = 0; c < node_count; ++c) node_rank_[nodes[c]] = std::min(node_rank_[nodes[c]], rank);
}

// (D2): the node's owner, which also adds its elements' entries there when it has elements
void TangentParts::add_node(int I, const int* positions, int count) {
  const int owner = node_rank_[I] == kNone ? 0 : node_rank_[I];
  owns_node_[I] = owner == me_;
  for (int q = 0; q < count; ++q)
    if (positions[q] >= 0) touch(positions[q], owner);
}

void TangentParts::add_first_rank(const int* positions, int count) {
  for (int q = 0; q < count; ++q)
    if (positions[q] >= 0) touch(positions[q], 0);
}

// (D3): a position is held by the lowest rank adding to it; one nobody adds to (a zero of the
// pattern) by rank 0, which keeps it in the factorization's pattern
void TangentParts::finish() {
  held_.clear();
  shared_.clear();
  for (int p = 0; p < static_cast<int>(lowest_.size()); ++p) {
    const int lowest = lowest_[p] == kNone ? 0 : lowest_[p];
    if (lowest == me_) held_.push_back(p);
    if (highest_[p] > lowest) shared_.push_back(p);
  }
  buffer_.resize(shared_.size());
  std::vector<int>().swap(lowest_);
  std::vector<int>().swap(highest_);
  std::vector<int>().swap(node_rank_);
  share_ = nullptr;
  built_ = true;
}

// (D4): the interface entries' partial sums, added over the ranks; a rank that adds nothing there
// contributes zero
void TangentParts::sum_shared(double* values) {
  for (std::size_t q = 0; q < shared_.size(); ++q) buffer_[q] = values[shared_[q]];
  sum_over_ranks(buffer_.data(), buffer_.size());
  for (std::size_t q = 0; q < shared_.size(); ++q) values[shared_[q]] = buffer_[q];
}

}  // namespace ff
