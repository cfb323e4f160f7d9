#include "core/assembly/dof_map.h"

namespace ff::assembly {

DofMap::DofMap(int node_count, const std::function<bool(int node, int slot)>& is_unknown) {
  equation_.assign(6 * static_cast<std::size_t>(node_count), -1);
  for (int i = 0; i < node_count; ++i)
    for (int s = 0; s < 6; ++s)
      if (is_unknown(i, s)) {
        equation_[6 * i + s] = static_cast<int>(unknowns_.size());
        unknowns_.push_back({i, s});
      }
}

}  // namespace ff::assembly
