#include "kernels/hopfield/hopfield_decode.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

#include "kernels/assignment/lap.hpp"

namespace trackassoc {

bool is_valid_state(std::span<const uint8_t> V, int32_t n1, int32_t n2, int32_t n3) {
  std::vector<uint8_t> ui(n1, 0), uj(n2, 0), uk(n3, 0);
  int64_t count = 0;
  std::size_t a = 0;
  for (int32_t i = 0; i < n1; ++i)
    for (int32_t j = 0; j < n2; ++j)
      for (int32_t k = 0; k < n3; ++k, ++a) {
        if (!V[a]) continue;
        if (ui[i] || uj[j] || uk[k]) return false;
        ui[i] = uj[j] = uk[k] = 1;
        ++count;
      }
  return count == std::min({n1, n2, n3});
}

std::vector<uint32_t> active_by_cost(std::span<const uint8_t> V, const CostTensor3& cost) {
  std::vector<uint32_t> on;
  for (std::size_t a = 0; a < V.size(); ++a)
    if (V[a]) on.push_back(static_cast<uint32_t>(a));
  std::stable_sort(on.begin(), on.end(), [&](uint32_t x, uint32_t y) { return cost.cost[x] < cost.cost[y]; });
  return on;
}

std::vector<uint32_t> active_by_output(std::span<const float> V, float threshold) {
  std::vector<uint32_t> on;
  for (std::size_t a = 0; a < V.size(); ++a)
    if (V[a] > threshold) on.push_back(static_cast<uint32_t>(a));
  std::stable_sort(on.begin(), on.end(), [&](uint32_t x, uint32_t y) { return V[x] > V[y]; });
  return on;
}

namespace {

struct FreeSets {
  std::vector<uint8_t> ui, uj, uk;
};

}  // namespace

std::vector<Tuple3> repair_assignment(const CostTensor3& cost, std::span<const uint32_t> priority,
                                      HopfieldRepair method) {
  const int32_t n1 = cost.n1, n2 = cost.n2, n3 = cost.n3;
  const int32_t m = std::min({n1, n2, n3});
  FreeSets used{std::vector<uint8_t>(n1, 0), std::vector<uint8_t>(n2, 0), std::vector<uint8_t>(n3, 0)};
  std::vector<Tuple3> tuples;
  tuples.reserve(m);
  auto take = [&](int32_t i, int32_t j, int32_t k) {
    if (used.ui[i] || used.uj[j] || used.uk[k]) return;
    used.ui[i] = used.uj[j] = used.uk[k] = 1;
    tuples.push_back({i, j, k});
  };
  for (uint32_t a : priority) {
    const int32_t k = static_cast<int32_t>(a % n3);
    const int32_t j = static_cast<int32_t>((a / n3) % n2);
    const int32_t i = static_cast<int32_t>(a / (static_cast<uint32_t>(n3) * n2));
    take(i, j, k);
  }
  if (static_cast<int32_t>(tuples.size()) == m) return tuples;
  std::vector<int32_t> fi, fj, fk;
  for (int32_t i = 0; i < n1; ++i)
    if (!used.ui[i]) fi.push_back(i);
  for (int32_t j = 0; j < n2; ++j)
    if (!used.uj[j]) fj.push_back(j);
  for (int32_t k = 0; k < n3; ++k)
    if (!used.uk[k]) fk.push_back(k);
  if (method == HopfieldRepair::kLap) {
    // Sequential pairwise LAPs on the free sub-tensor: (i, j) by c12 = min_k b_ijk, then the
    // pairs against the free k.
    const int32_t a = static_cast<int32_t>(fi.size()), b = static_cast<int32_t>(fj.size()),
                  c = static_cast<int32_t>(fk.size());
    std::vector<double> c12(static_cast<std::size_t>(a) * b);
    for (int32_t x = 0; x < a; ++x)
      for (int32_t y = 0; y < b; ++y) {
        float best = std::numeric_limits<float>::infinity();
        for (int32_t z = 0; z < c; ++z) best = std::min(best, cost.at(fi[x], fj[y], fk[z]));
        c12[static_cast<std::size_t>(x) * b + y] = best;
      }
    const LapResult first = solve_lap(c12, a, b);
    std::vector<std::pair<int32_t, int32_t>> pairs;
    for (int32_t x = 0; x < a; ++x)
      if (first.row_to_col[x] >= 0) pairs.push_back({fi[x], fj[first.row_to_col[x]]});
    const int32_t p = static_cast<int32_t>(pairs.size());
    std::vector<double> c3(static_cast<std::size_t>(p) * c);
    for (int32_t x = 0; x < p; ++x)
      for (int32_t z = 0; z < c; ++z)
        c3[static_cast<std::size_t>(x) * c + z] = cost.at(pairs[x].first, pairs[x].second, fk[z]);
    const LapResult second = solve_lap(c3, p, c);
    for (int32_t x = 0; x < p; ++x)
      if (second.row_to_col[x] >= 0) take(pairs[x].first, pairs[x].second, fk[second.row_to_col[x]]);
    if (static_cast<int32_t>(tuples.size()) == m) return tuples;
    // (only with +inf costs can the LAPs leave indices; the greedy pass below completes them)
    fi.clear();
    fj.clear();
    fk.clear();
    for (int32_t i = 0; i < n1; ++i)
      if (!used.ui[i]) fi.push_back(i);
    for (int32_t j = 0; j < n2; ++j)
      if (!used.uj[j]) fj.push_back(j);
    for (int32_t k = 0; k < n3; ++k)
      if (!used.uk[k]) fk.push_back(k);
  }
  // Complete on the free sub-tensor: cheapest free tuple first.
  std::vector<uint32_t> free_tuples;
  free_tuples.reserve(fi.size() * fj.size() * fk.size());
  for (int32_t i : fi)
    for (int32_t j : fj)
      for (int32_t k : fk) free_tuples.push_back(static_cast<uint32_t>(cost.index(i, j, k)));
  std::sort(free_tuples.begin(), free_tuples.end(), [&](uint32_t x, uint32_t y) {
    return cost.cost[x] < cost.cost[y] || (cost.cost[x] == cost.cost[y] && x < y);
  });
  for (uint32_t a : free_tuples) {
    const int32_t k = static_cast<int32_t>(a % n3);
    const int32_t j = static_cast<int32_t>((a / n3) % n2);
    const int32_t i = static_cast<int32_t>(a / (static_cast<uint32_t>(n3) * n2));
    take(i, j, k);
    if (static_cast<int32_t>(tuples.size()) == m) break;
  }
  return tuples;
}

}  // namespace trackassoc
