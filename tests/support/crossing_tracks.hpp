// Aligned tracks crossing one another, for the per-scan index's count filter
// (tests/kernels/statistics/test_scan_candidates_{sensors,skip}.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc::testing_support {

// n tracks of one sensor crossing one another: uniform start in a 6 km square, velocity ±150 m per
// step on each axis, position variance 1e4..5e4 m², over a random span of the K common times, valid
// at ~80 % of it. Most pairs are within their per-scan bound at a few scans only (as they pass).
// `mixed`: a third of the tracks over every common time and a third over a random span, both valid
// at each scan (no gaps), the last third as above.
inline AlignedTracks crossing_sensor(int32_t sensor, int32_t n, int32_t K, uint64_t seed,
                                     bool mixed = false) {
  AlignedTracks x;
  x.sensor = sensor;
  x.dim = 4;
  x.n_times = K;
  CounterRng rng(seed, 0, 0);
  std::vector<int32_t> begin, length;
  auto whole = [&](int32_t i) { return mixed && i % 3 == 0; };
  auto gaps = [&](int32_t i) { return !mixed || i % 3 == 2; };
  for (int32_t i = 0; i < n; ++i) {
    x.track.push_back(i);
    x.truth.push_back(i);
    const auto b = whole(i) ? 0 : static_cast<int32_t>(rng.uniform(0.0, K / 2.0));
    begin.push_back(b);
    length.push_back(whole(i) ? K : 1 + static_cast<int32_t>(rng.uniform(K / 4.0, K - b - 1.0)));
  }
  x.allocate(begin, length);
  for (int32_t i = 0; i < n; ++i) {
    const double p0[2] = {rng.uniform(-3000.0, 3000.0), rng.uniform(-3000.0, 3000.0)};
    const double v[2] = {rng.uniform(-150.0, 150.0), rng.uniform(-150.0, 150.0)};
    const double var = rng.uniform(1e4, 5e4);
    for (int32_t k = x.span(i).begin; k < x.span(i).end; ++k) {
      const int64_t c = x.cell(i, k);
      x.valid[c] = !gaps(i) || rng.uniform(0.0, 1.0) < 0.8;
      double* st = x.state_at(c);
      for (int d = 0; d < 2; ++d) st[d] = p0[d] + v[d] * k, st[2 + d] = v[d];
      double* p = x.cov_at(c);
      for (int r = 0; r < 4; ++r) p[packed_index(4, r, r)] = r < 2 ? var : 100.0;
    }
  }
  return x;
}

}  // namespace trackassoc::testing_support
