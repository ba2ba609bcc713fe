// Geometric 3-sensor tracking instances for testing and measuring the 3-D assignment solvers
// (docs/design.md §4.4 "Measure against the strong simple baseline"). Pure: no files, no global state.
//
// n targets are drawn uniformly in a square of side `side`; each of the three sensors reports a
// noisy copy of every target position (isotropic Gaussian noise, σ_s per sensor), with its local
// track numbers shuffled. The cost is the chain form of seed 000 Eq. 3 with the squared
// Mahalanobis distance of the two position estimates,
//   λ_ij = |p¹_i − p²_j|² / (σ₁² + σ₂²),   b_ijk = λ_ij + λ_jk,
// so the true association has b ≈ χ²₄ per tuple. `noise_to_spacing` = σ / (side/√n) sets the
// difficulty: 0.1 is nearly trivial, 0.5 makes greedy err often, 1.0 is dense.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {

struct GeometricInstanceOptions {
  int32_t n = 20;
  double side = 100e3;            // [m]
  double noise_to_spacing = 0.5;  // σ₂ / (side / √n); sensors 1 and 3 use 0.8σ and 1.2σ
};

struct GeometricInstance {
  CostTensor3 cost;
  std::vector<Tuple3> truth;  // the true association (one tuple per target)
};

inline GeometricInstance make_geometric_instance(const GeometricInstanceOptions& o, uint64_t seed,
                                                 uint64_t instance = 0) {
  const int32_t n = o.n;
  CounterRng rng(seed, instance, 0x3d3d);
  std::vector<double> tx(n), ty(n);
  for (int32_t t = 0; t < n; ++t) {
    tx[t] = rng.uniform(0.0, o.side);
    ty[t] = rng.uniform(0.0, o.side);
  }
  const double sigma = o.noise_to_spacing * o.side / std::sqrt(static_cast<double>(std::max(n, 1)));
  const double sig[3] = {0.8 * sigma, sigma, 1.2 * sigma};
  // perm[s][track] = target reported as local track `track` of sensor s.
  std::vector<std::vector<int32_t>> perm(3, std::vector<int32_t>(n));
  std::vector<std::vector<double>> px(3, std::vector<double>(n)), py(3, std::vector<double>(n));
  for (int s = 0; s < 3; ++s) {
    std::iota(perm[s].begin(), perm[s].end(), 0);
    rng.shuffle(std::span<int32_t>(perm[s]));
    for (int32_t tr = 0; tr < n; ++tr) {
      px[s][tr] = tx[perm[s][tr]] + rng.normal(0.0, sig[s]);
      py[s][tr] = ty[perm[s][tr]] + rng.normal(0.0, sig[s]);
    }
  }
  auto lambda = [&](int s, int32_t a, int t, int32_t b) {
    const double dx = px[s][a] - px[t][b], dy = py[s][a] - py[t][b];
    return (dx * dx + dy * dy) / (sig[s] * sig[s] + sig[t] * sig[t]);
  };
  GeometricInstance inst;
  inst.cost = CostTensor3(n, n, n);
  std::vector<double> l12(static_cast<std::size_t>(n) * n), l23(static_cast<std::size_t>(n) * n);
  for (int32_t a = 0; a < n; ++a)
    for (int32_t b = 0; b < n; ++b) {
      l12[static_cast<std::size_t>(a) * n + b] = lambda(0, a, 1, b);
      l23[static_cast<std::size_t>(a) * n + b] = lambda(1, a, 2, b);
    }
  for (int32_t i = 0; i < n; ++i)
    for (int32_t j = 0; j < n; ++j)
      for (int32_t k = 0; k < n; ++k)
        inst.cost.at(i, j, k) = static_cast<float>(l12[static_cast<std::size_t>(i) * n + j] +
                                                   l23[static_cast<std::size_t>(j) * n + k]);
  std::vector<std::vector<int32_t>> track_of(3, std::vector<int32_t>(n));
  for (int s = 0; s < 3; ++s)
    for (int32_t tr = 0; tr < n; ++tr) track_of[s][perm[s][tr]] = tr;
  for (int32_t t = 0; t < n; ++t) inst.truth.push_back({track_of[0][t], track_of[1][t], track_of[2][t]});
  return inst;
}

}  // namespace trackassoc
