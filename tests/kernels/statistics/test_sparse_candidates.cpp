// Sparse candidates (kernels/statistics/sparse_candidates.hpp): the grid returns exactly the pairs of the
// all-pairs scan of the same bound; no pair the dense statistic gates in is lost; λ on candidate
// pairs equals the dense λ bit for bit; 1 vs 2 threads; the radius by hand.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <set>
#include <utility>

#include "kernels/core/error.hpp"
#include "kernels/statistics/sparse_candidates.hpp"
#include "tests/support/sparse_fixtures.hpp"

namespace trackassoc {
namespace {

std::array<AlignedTracks, 3> aligned_three(const TrackFile& f) {
  std::vector<double> grid;  // every sensor has reported by t = 3 s (fixture offsets < 1 s, periods ≤ 2 s)
  for (double t = 3.0; t <= 29.0; t += 2.0) grid.push_back(t);
  std::array<AlignedTracks, 3> a;
  AlignmentOptions forward;  // seed 000's alignment, the setting of this index's scale study
  forward.method = AlignmentMethod::kForward;
  forward.process_noise = 1.0;
  for (int d = 0; d < 3; ++d) a[d] = align_tracks(f.tracks, d + 1, grid, forward);
  return a;
}

std::set<std::pair<int32_t, int32_t>> as_set(const CandidatePairs& c) {
  std::set<std::pair<int32_t, int32_t>> s;
  for (std::size_t q = 0; q < c.size(); ++q) s.insert({c.a[q], c.b[q]});
  return s;
}

// (3-D or 2-D, seed, tracks with births and deaths at different times or not)
class SparseCandidates : public ::testing::TestWithParam<std::tuple<bool, uint64_t, bool>> {};

TEST_P(SparseCandidates, GridEqualsScanAndLosesNoGatedPair) {
  testing::SyntheticSpec spec;
  spec.three_d = std::get<0>(GetParam());
  spec.seed = std::get<1>(GetParam());
  spec.targets = 120;
  spec.box = spec.box_z = 4000.0;  // dense: many near neighbours, many candidates per track
  spec.p_seen = 0.9;
  if (std::get<2>(GetParam())) spec.min_lifetime_fraction = 0.3;  // partial tracks: the conservative bound
  const TrackFile f = testing::synthetic_track_file(spec);
  const auto al = aligned_three(f);
  StatisticOptions so;  // the χ²(n·D) gate, whose bound this index implements
  so.gate = GateMethod::kChiSquareSum;
  so.gate_probability = 0.99;
  const CandidateOptions co{so.gate_probability, 1.0};
  std::size_t gated_in = 0, total_candidates = 0;
  for (auto [x, y] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{0, 2}}) {
    const CandidatePairs grid = gated_candidate_pairs(al[x], al[y], co);
    const CandidatePairs scan = gated_candidate_pairs_all_pairs(al[x], al[y], co);
    EXPECT_EQ(grid.a, scan.a);  // same pairs, same order
    EXPECT_EQ(grid.b, scan.b);
    total_candidates += grid.size();
    // Lossless against the dense statistic, full and partial tracks alike.
    const PairStatistic dense = independent_sequential_statistic(al[x], al[y], so);
    const auto cand = as_set(grid);
    for (int32_t i = 0; i < dense.n_a; ++i)
      for (int32_t j = 0; j < dense.n_b; ++j)
        if (dense.in_gate[static_cast<std::size_t>(i) * dense.n_b + j]) {
          ++gated_in;
          EXPECT_TRUE(cand.count({i, j})) << "gated-in pair " << i << "," << j << " lost";
        }
    // λ on candidates is the dense λ, bit for bit, and so is the gate.
    const SparsePairStatistic sp = sparse_sequential_statistic(al[x], al[y], grid, so);
    for (std::size_t q = 0; q < sp.size(); ++q) {
      const std::size_t idx = static_cast<std::size_t>(sp.a[q]) * dense.n_b + sp.b[q];
      EXPECT_EQ(sp.lambda[q], dense.lambda[idx]);
      EXPECT_EQ(sp.dof[q], dense.dof[idx]);
      EXPECT_EQ(sp.in_gate[q], dense.in_gate[idx]);
      EXPECT_EQ(sp.find(sp.a[q], sp.b[q]), static_cast<int64_t>(q));
    }
    const SparsePairStatistic kept = keep_in_gate(sp);
    for (std::size_t q = 0; q < kept.size(); ++q) EXPECT_EQ(kept.in_gate[q], 1);
  }
  EXPECT_GT(gated_in, 0u);
  // With full tracks the index must prune: far fewer candidates than the 3·n² pairs. (Partial
  // tracks use the conservative radius, which in this 4 km box spans most of it.)
  if (!std::get<2>(GetParam())) {
    EXPECT_LT(total_candidates, 3u * 120u * 120u / 4u);
  }
}

INSTANTIATE_TEST_SUITE_P(RandomScenarios, SparseCandidates,
                         ::testing::Combine(::testing::Bool(), ::testing::Values(1u, 2u, 3u),
                                            ::testing::Bool()));

TEST(SparseCandidates, OneAndTwoThreadsIdentical) {
  testing::SyntheticSpec spec;
  spec.targets = 300;
  const TrackFile f = testing::synthetic_track_file(spec);
  const auto al = aligned_three(f);
  const CandidateOptions co{0.99, 1.0};
  StatisticOptions so;
  so.gate = GateMethod::kChiSquareSum;
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    const CandidatePairs c = gated_candidate_pairs(al[0], al[1], co);
    return std::make_pair(c, sparse_sequential_statistic(al[0], al[1], c, so));
  };
  const auto one = run(1), two = run(2);
  EXPECT_EQ(one.first.a, two.first.a);
  EXPECT_EQ(one.first.b, two.first.b);
  EXPECT_EQ(one.second.lambda, two.second.lambda);
}

// Hand example: 2-D (D = 4), one common time, P_a = P_b = I. σ²_a + σ²_b = 2 and
// χ²_0.99(4) = 13.2767 (table), so the radius² is 26.553: a mean distance of 5.15 (26.52) is a
// candidate, 5.16 (26.63) is not.
TEST(SparseCandidates, RadiusByHand) {
  auto make = [](int32_t sensor, double x) {
    AlignedTracks t;
    t.sensor = sensor;
    t.dim = 4;
    t.n_times = 1;
    t.track = {0};
    t.truth = {-1};
    t.state = {x, 0, 0, 0};
    t.cov.assign(10, 0.0);
    for (int c = 0; c < 4; ++c) t.cov[packed_index(4, c, c)] = 1.0;
    t.valid = {1};
    t.span_begin = {0};
    t.span_offset = {0, 1};
    return t;
  };
  const CandidateOptions co{0.99, 1.0};
  EXPECT_EQ(gated_candidate_pairs(make(1, 0.0), make(2, 5.15), co).size(), 1u);
  EXPECT_EQ(gated_candidate_pairs(make(1, 0.0), make(2, 5.16), co).size(), 0u);
  EXPECT_EQ(gated_candidate_pairs(make(1, 0.0), make(2, -5.15), co).size(), 1u);
  const CandidateOptions wider{0.99, 1.1};  // radius × 1.1
  EXPECT_EQ(gated_candidate_pairs(make(1, 0.0), make(2, 5.6), wider).size(), 1u);
  const TrackIndexKeys keys = track_index_keys(make(1, 3.0));
  EXPECT_EQ(keys.mean_position[0], 3.0);
  EXPECT_EQ(keys.max_position_variance[0], 1.0);
  EXPECT_EQ(keys.valid_times[0], 1);
}

TEST(SparseCandidates, BadOptionsAndInputs) {
  EXPECT_THROW((CandidateOptions{1.0, 1.0}.validate()), InputError);  // no gate: n² candidates
  EXPECT_THROW((CandidateOptions{0.99, 0.5}.validate()), InputError);
  EXPECT_THROW((CandidateOptions{0.99, NAN}.validate()), InputError);
  AlignedTracks a, b;
  a.dim = 4;
  b.dim = 6;
  EXPECT_THROW(gated_candidate_pairs(a, b, CandidateOptions{}), InputError);
  // Empty sensors: no candidates, no crash.
  b.dim = 4;
  EXPECT_EQ(gated_candidate_pairs(a, b, CandidateOptions{}).size(), 0u);
  CandidatePairs unsorted;
  EXPECT_EQ(sparse_sequential_statistic(a, b, unsorted, StatisticOptions{}).size(), 0u);
  unsorted.a = {0};
  unsorted.b = {0};
  EXPECT_THROW(sparse_sequential_statistic(a, b, unsorted, StatisticOptions{}), InputError);
}

}  // namespace
}  // namespace trackassoc
