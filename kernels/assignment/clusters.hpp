// Connected components of the candidate graph (docs/design.md §4.3, "Sparse form").
//
// Nodes are the local tracks of all sensors (sensor s's track i is node offset[s] + i); an edge
// joins two tracks of different sensors whose pair is inside the gate. No gated-in tuple and no
// gated-in pair crosses two components, so the components are independent assignment
// subproblems: a tuple with a track from each of two components has a gated-out pair, which the
// cost tensor charges `gated_pair_cost` and the decoding splits anyway.
//
// Algorithm: union-find with path halving and union by size (Tarjan 1975), O(E·α(N)); then one
// pass labels the components in the order of their smallest node, so the labelling is
// deterministic whatever the edge order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace trackassoc {

class UnionFind {
 public:
  explicit UnionFind(int32_t n);
  int32_t find(int32_t x);
  // Returns true when x and y were in different sets.
  bool unite(int32_t x, int32_t y);

 private:
  std::vector<int32_t> parent_, size_;
};

struct Components {
  int32_t count = 0;
  std::vector<int32_t> label;  // component of each node, 0..count-1, by smallest node
  std::vector<int64_t> begin;  // count+1 offsets into `nodes`
  std::vector<int32_t> nodes;  // members of each component, ascending
  int32_t size(int32_t c) const { return static_cast<int32_t>(begin[c + 1] - begin[c]); }
  std::span<const int32_t> members(int32_t c) const {
    return {nodes.data() + begin[c], static_cast<std::size_t>(begin[c + 1] - begin[c])};
  }
};

// Edges (u[e], v[e]); nodes in [0, n). Throws InputError on an out-of-range node.
Components connected_components(int32_t n, std::span<const int32_t> u, std::span<const int32_t> v);

}  // namespace trackassoc
