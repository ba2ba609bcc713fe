// Rival-weighted link costs of the default pipeline (engine/pipeline/sparse_sd_pipeline.hpp,
// rival_link_costs; docs/design.md §4.9), against hand-built pairs and independent thresholds:
//  * m counts a track's gated partners that coexist with its pair's other track (sequential
//    fragments of one target are no rivals), and the larger side counts;
//  * the threshold is the calibrated gate f·χ²_p(n·D/f) (f = min(5, n)) at p(m) = 1 − (1 − p)·m²,
//    computed here from chi_square_quantile, the cost the excess over it per independent scan
//    (λ − G)/5, and m = 1 (or κ = 0) is the gate's own link cost;
//  * on dense parallel traffic (recorded_bias_dense without its registration errors, 10 runs) it
//    makes fewer false tuples than the unweighted cost, and no fewer correct targets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/track_file.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

// The calibrated gate at probability p over n scans, written out (kernels/statistics/
// association_statistic.hpp's header): f·χ²_p(n·D/f), f = min(5, n).
double calibrated_threshold(double p, int32_t n, int dim) {
  const double f = std::min(5.0, static_cast<double>(n));
  return f * chi_square_quantile(p, n * dim / f);
}

// The default link cost of an excess over the gate: per independent scan, (λ − G)/f with
// StatisticOptions' f = 5 (kernels/statistics/association_statistic.hpp).
double per_independent_scan(double excess) { return excess / 5.0; }

// Sensor a: tracks a0, a1, a2; sensor b: tracks b0..b4, with valid common-time intervals
//   a0 [0, 10], a1 [0, 20], a2 [0, 20]; b0 [0, 10], b1 [2, 8], b2 [0, 9], b3 [12, 20], b4 [5, 10].
// Gated pairs: a0 with b0, b1, b4 (which coexist: m = 3); a1 with b2 and with b3, which follows b2
// without overlap (no rival of it); a2 with b2 (b2 has a1 and a2, which coexist: m = 2).
struct Hand {
  AlignedSensors sensors;
  SparsePairStatistic st;
};

Hand hand_built() {
  Hand h;
  h.sensors.dim = 4;
  h.sensors.offset = {0, 3, 8};
  h.sensors.first_valid = {0, 0, 0, 0, 2, 0, 12, 5};
  h.sensors.last_valid = {10, 20, 20, 10, 8, 9, 20, 10};
  h.st.n_a = 3;
  h.st.n_b = 5;
  h.st.a = {0, 0, 0, 1, 1, 2};
  h.st.b = {0, 1, 4, 2, 3, 2};
  h.st.lambda = {20.0, 30.0, 15.0, 12.0, 40.0, 25.0};
  h.st.dof = {40, 28, 24, 40, 36, 32};  // n = 10, 7, 6, 10, 9, 8 scans
  h.st.in_gate.assign(6, 1);
  return h;
}

TEST(RivalLinkCosts, TightenTheGateByTheSquareOfTheCoexistingRivals) {
  const Hand h = hand_built();
  const StatisticOptions so;  // calibrated, p = 0.99, per independent scan
  const SequentialGate gate(4, so, 32);
  const std::vector<double> link = rival_link_costs(h.st, h.sensors, 0, 1, gate, so, 2.0);
  const int32_t m[] = {3, 3, 3, 2, 1, 2};
  ASSERT_EQ(link.size(), 6u);
  for (std::size_t q = 0; q < 6; ++q) {
    const int32_t n = h.st.dof[q] / 4;
    const double p = 1.0 - 0.01 * m[q] * m[q];  // 0.91, 0.96, 0.99
    const double expected = per_independent_scan(h.st.lambda[q] - calibrated_threshold(p, n, 4));
    EXPECT_NEAR(link[q], expected, 1e-9) << "pair " << q << ", m = " << m[q];
  }
  // m = 1: the gate's own link cost; every tightened pair costs more than it did.
  EXPECT_NEAR(link[4], gate.link_cost(40.0, 9), 1e-12);
  for (std::size_t q : {0u, 1u, 2u, 3u, 5u})
    EXPECT_GT(link[q], gate.link_cost(h.st.lambda[q], h.st.dof[q] / 4) + 0.1) << q;
  // κ = 0 is the unweighted cost for every pair.
  const std::vector<double> off = rival_link_costs(h.st, h.sensors, 0, 1, gate, so, 0.0);
  for (std::size_t q = 0; q < 6; ++q) EXPECT_EQ(off[q], gate.link_cost(h.st.lambda[q], h.st.dof[q] / 4));
  // Without b4 (pairs 0, 1 and 3-5): a0's rivals are b0 and b1, m = 2.
  Hand g = hand_built();
  for (auto* v : {&g.st.a, &g.st.b, &g.st.dof}) v->erase(v->begin() + 2);
  g.st.lambda.erase(g.st.lambda.begin() + 2);
  g.st.in_gate.erase(g.st.in_gate.begin() + 2);
  const std::vector<double> two = rival_link_costs(g.st, g.sensors, 0, 1, gate, so, 2.0);
  EXPECT_NEAR(two[0], per_independent_scan(20.0 - calibrated_threshold(0.96, 10, 4)), 1e-9);
}

TEST(RivalLinkCosts, NoTighterThanTheMedianAndValidated) {
  // 9 coexisting partners: 1 − 0.01·81 < 0.5, so the gate at p = 0.5.
  AlignedSensors s;
  s.dim = 4;
  s.offset = {0, 1, 10};
  s.first_valid.assign(10, 0);
  s.last_valid.assign(10, 10);
  SparsePairStatistic st;
  st.n_a = 1, st.n_b = 9;
  for (int32_t j = 0; j < 9; ++j) {
    st.a.push_back(0), st.b.push_back(j), st.lambda.push_back(10.0 + j), st.dof.push_back(40);
    st.in_gate.push_back(1);
  }
  const StatisticOptions so;
  const std::vector<double> link = rival_link_costs(st, s, 0, 1, SequentialGate(4, so, 16), so, 2.0);
  for (int32_t j = 0; j < 9; ++j)
    EXPECT_NEAR(link[j], per_independent_scan(10.0 + j - calibrated_threshold(0.5, 10, 4)), 1e-9);
  SparseSDOptions bad;
  bad.rival_exponent = -1.0;
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(RivalLinkCosts, FewerFalseTuplesInDenseParallelTraffic) {
  // recorded_bias_dense without its registration errors: the airway's neighbours alone.
  Scenario sc = load_scenario("recorded_bias_dense");
  sc.sensor_errors.clear();
  int32_t false_weighted = 0, false_plain = 0, correct_weighted = 0, correct_plain = 0;
  for (int run = 0; run < 10; ++run) {
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, run));
    SparseSDOptions weighted, plain;
    plain.rival_exponent = 0.0;
    for (auto [options, fa, co] : {std::tuple{&weighted, &false_weighted, &correct_weighted},
                                   std::tuple{&plain, &false_plain, &correct_plain}}) {
      const AssociationRecord rec = associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, *options);
      const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
      *fa += m.false_tuples;
      *co += m.correct;
    }
  }
  // Measured (10 runs, seed 1): 17 -> 12 false tuples, 548 -> 554 correct targets.
  EXPECT_LE(false_weighted, false_plain - 3);
  EXPECT_GE(correct_weighted, correct_plain);
}

}  // namespace
}  // namespace trackassoc
