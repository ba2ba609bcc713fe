#include "kernels/hopfield_decode.hpp"

#include <algorithm>
#include <numeric>

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
  // Complete on the free sub-tensor: cheapest free tuple first.
  std::vector<int32_t> fi, fj, fk;
  for (int32_t i = 0; i < n1; ++i)
    if (!used.ui[i]) fi.push_back(i);
  for (int32_t j = 0; j < n2; ++j)
    if (!used.uj[j]) fj.push_back(j);
  for (int32_t k = 0; k < n3; ++k)
    if (!used.uk[k]) fk.push_back(k);
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
  (void)method;
  return tuples;
}

std::vector<uint8_t> assignment_state(const CostTensor3& cost, const std::vector<Tuple3>& tuples) {
  std::vector<uint8_t> V(cost.size(), 0);
  for (const auto& t : tuples) V[cost.index(t[0], t[1], t[2])] = 1;
  return V;
}

}  // namespace trackassoc
