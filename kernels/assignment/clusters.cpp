#include "kernels/assignment/clusters.hpp"

#include <numeric>
#include <string>

#include "kernels/core/error.hpp"

namespace trackassoc {

UnionFind::UnionFind(int32_t n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), 0); }

int32_t UnionFind::find(int32_t x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];  // path halving
    x = parent_[x];
  }
  return x;
}

bool UnionFind::unite(int32_t x, int32_t y) {
  x = find(x);
  y = find(y);
  if (x == y) return false;
  if (size_[x] < size_[y]) std::swap(x, y);
  parent_[y] = x;
  size_[x] += size_[y];
  return true;
}

Components connected_components(int32_t n, std::span<const int32_t> u, std::span<const int32_t> v) {
  require(n >= 0, "connected_components", "negative node count");
  require(u.size() == v.size(), "connected_components", "edge arrays differ in length");
  UnionFind uf(n);
  for (std::size_t e = 0; e < u.size(); ++e) {
    require(u[e] >= 0 && u[e] < n && v[e] >= 0 && v[e] < n, "connected_components",
            "edge " + std::to_string(e) + " has a node outside [0, " + std::to_string(n) + ")");
    uf.unite(u[e], v[e]);
  }
  Components c;
  c.label.assign(n, -1);
  std::vector<int32_t> root_label(n, -1);
  for (int32_t x = 0; x < n; ++x) {
    const int32_t r = uf.find(x);
    if (root_label[r] < 0) root_label[r] = c.count++;
    c.label[x] = root_label[r];
  }
  // Counting sort by label keeps members ascending.
  c.begin.assign(c.count + 1, 0);
  for (int32_t x = 0; x < n; ++x) ++c.begin[c.label[x] + 1];
  for (int32_t k = 0; k < c.count; ++k) c.begin[k + 1] += c.begin[k];
  c.nodes.resize(n);
  std::vector<int64_t> next(c.begin.begin(), c.begin.end() - 1);
  for (int32_t x = 0; x < n; ++x) c.nodes[next[c.label[x]]++] = x;
  return c;
}

}  // namespace trackassoc
