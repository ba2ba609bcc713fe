// Shared by the tests/test_hopfield_*.cpp suites: random tensors, states, weights and shapes.
#pragma once

#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_energy.hpp"

namespace trackassoc::hopfield_test {

inline CostTensor3 random_tensor(int32_t n1, int32_t n2, int32_t n3, uint64_t seed) {
  CostTensor3 t(n1, n2, n3);
  CounterRng rng(seed, 1);
  for (auto& b : t.cost) b = static_cast<float>(rng.uniform(0.0, 50.0));
  return t;
}

inline std::vector<uint8_t> random_state(std::size_t K, double p, CounterRng& rng) {
  std::vector<uint8_t> V(K);
  for (auto& v : V) v = rng.uniform() < p;
  return V;
}

// Weights with all five terms active, and an N that need not equal min(n).
inline HopfieldWeights some_weights(CounterRng& rng, int32_t N) {
  HopfieldWeights w;
  w.A = static_cast<float>(rng.uniform(0.5, 3.0));
  w.B = static_cast<float>(rng.uniform(0.5, 3.0));
  w.C = static_cast<float>(rng.uniform(0.5, 3.0));
  w.D = static_cast<float>(rng.uniform(0.0, 1.0));
  w.E = static_cast<float>(rng.uniform(0.5, 4.0));
  w.N = N;
  return w;
}

struct Dims {
  int32_t n1, n2, n3;
};
// A random permutation state of an n×n×n network (a valid assignment).
inline std::vector<uint8_t> permutation_state(int32_t n, CounterRng& rng) {
  std::vector<int32_t> pj(n), pk(n);
  std::iota(pj.begin(), pj.end(), 0);
  std::iota(pk.begin(), pk.end(), 0);
  rng.shuffle(std::span<int32_t>(pj));
  rng.shuffle(std::span<int32_t>(pk));
  std::vector<uint8_t> V(static_cast<std::size_t>(n) * n * n, 0);
  for (int32_t i = 0; i < n; ++i) V[(static_cast<std::size_t>(i) * n + pj[i]) * n + pk[i]] = 1;
  return V;
}

}  // namespace trackassoc::hopfield_test
