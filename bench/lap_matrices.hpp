// The LAP benchmark matrices, shared by bench/bench_lap.cpp and reproduced bit-for-bit by
// bench/lap_scipy.py (which re-implements CounterRng in numpy), so that ours and scipy's
// linear_sum_assignment solve the same matrices.
//
//   uniform:   c_ij = u_(i·n + j),  u_t = CounterRng(seed, n, 0).uniform() draw number t (t from 0),
//              i.e. uniform on [0, 1) in row-major order.
//   geometric: points a_i = (u_2i, u_2i+1) from stream (seed, n, 1) and b_j likewise from stream
//              (seed, n, 2), in the unit square; c_ij = |a_i − b_j|² (the squared-distance costs of
//              a tracking association, with many near-ties).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/random.hpp"

namespace trackassoc::bench {

inline constexpr uint64_t kLapSeed = 20261123;

inline std::vector<double> lap_uniform_matrix(int n) {
  CounterRng rng(kLapSeed, static_cast<uint64_t>(n), 0);
  std::vector<double> c(static_cast<std::size_t>(n) * n);
  for (auto& x : c) x = rng.uniform();
  return c;
}

inline std::vector<double> lap_geometric_matrix(int n) {
  CounterRng ra(kLapSeed, static_cast<uint64_t>(n), 1), rb(kLapSeed, static_cast<uint64_t>(n), 2);
  std::vector<double> ax(n), ay(n), bx(n), by(n);
  for (int i = 0; i < n; ++i) {
    ax[i] = ra.uniform();
    ay[i] = ra.uniform();
  }
  for (int j = 0; j < n; ++j) {
    bx[j] = rb.uniform();
    by[j] = rb.uniform();
  }
  std::vector<double> c(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double dx = ax[i] - bx[j], dy = ay[i] - by[j];
      c[static_cast<std::size_t>(i) * n + j] = dx * dx + dy * dy;
    }
  return c;
}

}  // namespace trackassoc::bench
