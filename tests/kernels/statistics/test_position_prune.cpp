// The position-bound prune (kernels/statistics/gate_candidates.hpp) against its definition: a pair
// is kept when Σ min(term, c) ≤ G(n) over its n common valid scans and, for the calibrated gate, one
// term is at most c, each term d_pᵀ (P_a,pp + P_b,pp)⁻¹ d_p computed here by Eigen's inverse. With
// the calibrated gate's finite cap the prune stops summing a pair once the rest cannot take it past
// G(n); the tracks below have pairs kept that way (one target seen by both sensors) and pairs that
// pass close at first and part later (crossing targets), whose early terms alone would keep them.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "kernels/statistics/gate_candidates.hpp"
#include "tests/support/candidate_pairs.hpp"
#include "tests/support/crossing_tracks.hpp"

namespace trackassoc {
namespace {

using testing_support::crossing_sensor;
using testing_support::pairs_of;

struct Decision {
  bool kept = false;
  bool borderline = false;  // a sum or a term within 10⁻⁹ of its threshold: round-off may decide
};

Decision by_definition(const AlignedTracks& a, int32_t i, const AlignedTracks& b, int32_t j,
                       const SequentialGate& gate) {
  const double c = gate.cap();
  double bound = 0.0;
  int32_t n = 0, below = 0;
  Decision out;
  for (int32_t k = 0; k < a.n_times; ++k) {
    const int64_t ca = a.cell(i, k), cb = b.cell(j, k);
    if (ca < 0 || cb < 0 || !a.valid[ca] || !b.valid[cb]) continue;
    ++n;
    const double *xa = a.state_at(ca), *xb = b.state_at(cb), *pa = a.cov_at(ca), *pb = b.cov_at(cb);
    const Eigen::Vector2d d(xa[0] - xb[0], xa[1] - xb[1]);
    Eigen::Matrix2d C;
    C(0, 0) = pa[packed_index(4, 0, 0)] + pb[packed_index(4, 0, 0)];
    C(0, 1) = C(1, 0) = pa[packed_index(4, 0, 1)] + pb[packed_index(4, 0, 1)];
    C(1, 1) = pa[packed_index(4, 1, 1)] + pb[packed_index(4, 1, 1)];
    const double term = d.dot(C.inverse() * d);
    out.borderline = out.borderline || std::abs(term - c) <= 1e-9 * c;
    below += term <= c;
    bound += std::min(term, c);
  }
  if (n == 0) return out;
  const double G = gate.threshold(n);
  out.borderline = out.borderline || std::abs(bound - G) <= 1e-9 * G;
  out.kept = bound <= G && below > 0;
  return out;
}

TEST(PositionPrune, KeepsExactlyThePairsItsDefinitionKeeps) {
  for (const bool mixed : {false, true}) {
    SCOPED_TRACE(mixed ? "mixed spans" : "random spans");
    const int32_t n = 120, K = 40;
    // Sensor b sees sensor a's targets (the same seed: spans, positions and validity), 20-60 m off.
    const AlignedTracks a = crossing_sensor(0, n, K, 31, mixed);
    AlignedTracks b = crossing_sensor(1, n, K, 31, mixed);
    for (int32_t i = 0; i < n; ++i)
      for (int32_t k = b.span(i).begin; k < b.span(i).end; ++k) {
        double* x = b.state_at(b.cell(i, k));
        x[0] += 40.0 + 20.0 * std::sin(0.7 * k + i);
        x[1] -= 20.0 * std::cos(0.3 * k);
      }
    const StatisticOptions statistic;  // the calibrated gate: a finite cap
    const SequentialGate gate(4, statistic, K);
    ASSERT_TRUE(std::isfinite(gate.cap()));
    CandidatePairs every;
    every.n_a = every.n_b = n;
    for (int32_t i = 0; i < n; ++i)
      for (int32_t j = 0; j < n; ++j) every.a.push_back(i), every.b.push_back(j);
    const auto pruned = pairs_of(prune_by_position_bound(a, b, every, statistic));
    const std::set<std::pair<int32_t, int32_t>> kept(pruned.begin(), pruned.end());
    int32_t same_target = 0, other_targets = 0, dropped = 0, borderline = 0;
    for (int32_t i = 0; i < n; ++i)
      for (int32_t j = 0; j < n; ++j) {
        const Decision want = by_definition(a, i, b, j, gate);
        if (want.borderline) {
          ++borderline;
          continue;
        }
        EXPECT_EQ(kept.count({i, j}) == 1, want.kept) << "pair " << i << "," << j;
        if (want.kept) (i == j ? same_target : other_targets) += 1;
        dropped += !want.kept;
      }
    EXPECT_LE(borderline, 2);
    EXPECT_GT(same_target, n * 9 / 10);  // kept before their last terms
    EXPECT_GT(other_targets, 10);        // crossing targets kept too
    EXPECT_GT(dropped, n * n / 2);
  }
}

}  // namespace
}  // namespace trackassoc
