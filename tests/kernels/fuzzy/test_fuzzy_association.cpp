// Fuzzy association with temporary tracks and reliability (seed 001, kernels/fuzzy/fuzzy_association.hpp):
// memberships and synthesis functions against hand values, the synthesis-function axioms
// (Eq. 7–8), the errata (speeds, atan2, wrap-around), the reliability weighting changing the
// winner, and the association invariants (one target never split, separated targets never merged).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/fuzzy/fuzzy_association.hpp"
#include "tests/support/fuzzy_test_scenes.hpp"

using namespace trackassoc;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

SynthesisOptions synth(SynthesisFunction f, double q = 2.0) {
  SynthesisOptions o;
  o.function = f;
  o.q = q;
  return o;
}
}  // namespace

TEST(FuzzyMembership, GaussianHandValues) {
  EXPECT_DOUBLE_EQ(gaussian_membership(0.0, 400.0), 1.0);
  EXPECT_NEAR(gaussian_membership(400.0, 400.0), 0.36787944117144233, 1e-15);
  EXPECT_NEAR(gaussian_membership(800.0, 400.0), 0.01831563888873418, 1e-15);
  const auto m = fuzzy_memberships({400.0, 20.0, 0.35}, FactorScales{});  // u_max = 400, 40, 0.35
  EXPECT_NEAR(m[0], std::exp(-1.0), 1e-15);
  EXPECT_NEAR(m[1], std::exp(-0.25), 1e-15);
  EXPECT_NEAR(m[2], std::exp(-1.0), 1e-15);
}

TEST(FuzzySynthesis, HandValuesOfEq9To13) {
  const std::vector<double> M{0.9, 0.5, 0.2};
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kPowerMean, 2.0)), 0.6055300708194984,
              1e-14);                                                                       // √(1.1/3)
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kPowerMean, 1.0)), 1.6 / 3.0, 1e-14);  // mean
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kGeometricMean)), 0.4481404746557165,
              1e-14);                                                                // 0.09^(1/3)
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kWeightedMean)), 0.69, 1e-14);  // .495+.175+.02
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kWeightedPowerMean, 2.0)), 0.7328028384224504,
              1e-14);  // √(.4455+.0875+.004)
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kMinMaxMean)), 0.55, 1e-14);
  // Eq. 12 with q = 1 is Eq. 11.
  EXPECT_NEAR(synthesise(M, synth(SynthesisFunction::kWeightedPowerMean, 1.0)), 0.69, 1e-14);
}

TEST(FuzzySynthesis, MonotoneAndBetweenMinAndMax) {
  CounterRng rng(7);
  for (auto f :
       {SynthesisFunction::kPowerMean, SynthesisFunction::kGeometricMean, SynthesisFunction::kWeightedMean,
        SynthesisFunction::kWeightedPowerMean, SynthesisFunction::kMinMaxMean}) {
    for (double q : {0.5, 1.0, 2.0, 5.0}) {
      SynthesisOptions o = synth(f, q);
      for (int trial = 0; trial < 2000; ++trial) {
        // Random weights summing to 1 for Eq. 11–12.
        double a = rng.uniform(), b = rng.uniform() * (1 - a);
        o.weights = {a, b, 1 - a - b};
        std::vector<double> M{rng.uniform(), rng.uniform(), rng.uniform()};
        std::vector<double> N = M;
        for (auto& v : N) v = std::min(1.0, v + (rng.uniform() < 0.5 ? rng.uniform() * 0.3 : 0.0));
        const double s = synthesise(M, o), sn = synthesise(N, o);
        const double lo = *std::min_element(M.begin(), M.end()), hi = *std::max_element(M.begin(), M.end());
        ASSERT_LE(s, sn + 1e-12) << enum_name(f) << " q=" << q;  // Eq. 7
        ASSERT_GE(s, lo - 1e-12) << enum_name(f) << " q=" << q;  // Eq. 8
        ASSERT_LE(s, hi + 1e-12) << enum_name(f) << " q=" << q;
      }
    }
  }
}

TEST(FuzzySynthesis, ValidateAndParse) {
  SynthesisOptions o;
  o.weights = {0.5, 0.5, 0.5};
  EXPECT_THROW(o.validate(3), InputError);
  o.weights = {0.5, 0.5};
  EXPECT_THROW(o.validate(3), InputError);
  o = SynthesisOptions{};
  o.q = 0.0;
  EXPECT_THROW(o.validate(3), InputError);
  EXPECT_EQ(parse_enum<SynthesisFunction>("min-max-mean", "synthesis"), SynthesisFunction::kMinMaxMean);
  EXPECT_THROW(parse_enum<SynthesisFunction>("eq11", "synthesis"), InputError);
}

TEST(FuzzyReliability, NormalisedByTheMaximum) {
  const std::vector<double> w{1.0, 0.8, 1.0, 0.6};
  EXPECT_EQ(normalise_reliabilities(w), w);
  const std::vector<double> v{0.5, 0.25, 0.1};
  const auto n = normalise_reliabilities(v);
  EXPECT_DOUBLE_EQ(n[0], 1.0);
  EXPECT_DOUBLE_EQ(n[1], 0.5);
  EXPECT_DOUBLE_EQ(n[2], 0.2);
  EXPECT_THROW(normalise_reliabilities(std::vector<double>{0.0, 0.0}), InputError);
  EXPECT_THROW(normalise_reliabilities(std::vector<double>{1.0, -0.1}), InputError);
}

TEST(FuzzyFactorsTest, SpeedAndHeadingErrata) {
  // 359° vs 1°: 2°, not 358°.
  EXPECT_NEAR(heading_difference(359 * kDeg, 1 * kDeg), 2 * kDeg, 1e-12);
  EXPECT_NEAR(heading_difference(-179 * kDeg, 179 * kDeg), 2 * kDeg, 1e-12);
  EXPECT_NEAR(heading_difference(0.0, std::numbers::pi), std::numbers::pi, 1e-12);
  const double v = 300.0;
  const PlanarState a{0, 0, v * std::cos(359 * kDeg), v * std::sin(359 * kDeg)};
  const PlanarState b{30, 40, v * std::cos(1 * kDeg), v * std::sin(1 * kDeg)};
  const FuzzyFactors u = fuzzy_factors(a, b);
  EXPECT_NEAR(u.position, 50.0, 1e-12);
  EXPECT_NEAR(u.speed, 0.0, 1e-9);
  EXPECT_NEAR(u.heading, 2 * kDeg, 1e-12);
  // Opposite directions have equal speeds but a heading difference of π; arctan(y/x) would call
  // them equal.
  const FuzzyFactors w = fuzzy_factors({0, 0, 100, 100}, {0, 0, -100, -100});
  EXPECT_NEAR(w.speed, 0.0, 1e-12);
  EXPECT_NEAR(w.heading, std::numbers::pi, 1e-12);
  // Eq. 3 as printed (|x+y| of positions) would see 0 here; the speeds differ by 100 m/s.
  EXPECT_NEAR(fuzzy_factors({0, 0, 300, 0}, {0, 0, 0, 200}).speed, 100.0, 1e-12);
}

TEST(FuzzyAssociatorTest, ReliabilityWeightingChangesTheWinner) {
  // Sensor 0 is fully reliable, sensor 1 half. System track A (index 0) is last updated by
  // sensor 0 at x = 0, B (index 1) by sensor 1 at x = 1000 (outside A's 800 m gate, so it is new).
  // A temporary track from sensor 0 at x = 600 is 600 m from A and 400 m from B, with equal speed
  // and heading: S_A = 0.55·e^(−2.25) + 0.45 = 0.508, S_B = 0.55·e^(−1) + 0.45 = 0.652.
  // Unweighted: B. Weighted by the system track's reliability: 0.508 vs 0.326, A.
  const std::vector<double> rel{1.0, 0.5};
  auto run = [&](ReliabilityWeighting w) {
    FuzzyAssociationOptions o;
    o.weighting = w;
    FuzzyAssociator fc(o, rel, 3);
    fc.process(0, 0, 0.0, 0.0, 0.0);
    EXPECT_EQ(fc.process(0, 0, 1.0, 0.0, 100.0).system_track, 0);
    fc.process(1, 1, 0.0, 1000.0, 0.0);
    const auto b = fc.process(1, 1, 1.0, 1000.0, 100.0);
    EXPECT_TRUE(b.new_track);
    EXPECT_EQ(b.system_track, 1);
    fc.process(0, 2, 1.0, 600.0, 100.0);
    const auto d = fc.process(0, 2, 2.0, 600.0, 200.0);
    return d;
  };
  const auto none = run(ReliabilityWeighting::kNone);
  EXPECT_EQ(none.system_track, 1);
  EXPECT_NEAR(none.degree, 0.55 * std::exp(-1.0) + 0.45, 1e-12);
  EXPECT_EQ(run(ReliabilityWeighting::kTemporaryTrack).system_track, 1);  // same factor for all
  const auto sys = run(ReliabilityWeighting::kSystemTrack);
  EXPECT_EQ(sys.system_track, 0);
  EXPECT_NEAR(sys.degree, 0.55 * std::exp(-2.25) + 0.45, 1e-12);
  EXPECT_EQ(run(ReliabilityWeighting::kProduct).system_track, 0);
}

TEST(FuzzyAssociatorTest, SmoothsWithTheAlphaBetaFilter) {
  // Two plots start the system track at the temporary track's state; the third is an α-β update.
  FuzzyAssociationOptions o;
  o.smoother.gains = AlphaBetaGainMode::kFixed;
  o.smoother.alpha = 0.5;
  o.smoother.beta = 0.2;
  o.smoother.expanding_memory_start = false;
  const std::vector<double> rel{1.0};
  FuzzyAssociator fc(o, rel, 2);
  EXPECT_EQ(fc.process(0, 0, 0.0, 0.0, 0.0).system_track, -1);
  const auto d1 = fc.process(0, 0, 2.0, 20.0, 0.0);  // v = (10, 0)
  EXPECT_TRUE(d1.new_track);
  EXPECT_DOUBLE_EQ(d1.fused.vx, 10.0);
  fc.process(0, 1, 2.0, 22.0, 0.0);
  const auto d2 = fc.process(0, 1, 4.0, 44.0, 0.0);  // predicted 40, z = 44 → p = 42, v = 10 + 0.1·4
  EXPECT_EQ(d2.system_track, 0);
  EXPECT_DOUBLE_EQ(d2.fused.x, 42.0);
  EXPECT_DOUBLE_EQ(d2.fused.vx, 10.4);
}

TEST(FuzzyAssociatorTest, SingleTargetIsNeverSplit) {
  for (int run = 0; run < 20; ++run) {
    const auto scene = test_scenes::make_scene(1, run, {{-29500, 34500, 290, -400}}, 200.0);
    const FuzzyAssociationOptions options;
    const auto out = run_fuzzy_association(scene.spans(), scene.reliability, scene.num_local, options);
    EXPECT_EQ(out.num_system_tracks, 1) << "run " << run;
  }
}

TEST(FuzzyAssociatorTest, SeparatedTargetsAreNeverMerged) {
  for (int run = 0; run < 20; ++run) {
    // Two targets 5 km apart flying side by side, then two whose paths cross 15 s apart (closest
    // approach 2.1 km).
    for (const auto& targets : std::vector<std::vector<std::array<double, 4>>>{
             {{0, 0, 250, 0}, {0, 5000, 250, 0}}, {{-20000, 0, 200, 0}, {0, -23000, 0, 200}}}) {
      const auto scene = test_scenes::make_scene(2, run, targets, 150.0);
      const FuzzyAssociationOptions options;
      const auto out = run_fuzzy_association(scene.spans(), scene.reliability, scene.num_local, options);
      std::map<int32_t, std::set<int32_t>> targets_of;
      for (std::size_t i = 0; i < scene.size(); ++i)
        if (out.system_track[i] >= 0) targets_of[out.system_track[i]].insert(scene.target[i]);
      for (const auto& [trk, tgts] : targets_of) {
        EXPECT_EQ(tgts.size(), 1u) << "run " << run << " track " << trk;
      }
      EXPECT_EQ(out.num_system_tracks, 2) << "run " << run;
    }
  }
}

TEST(FuzzyAssociatorTest, TimeoutDropsStaleTracksAndBadInputIsRejected) {
  FuzzyAssociationOptions o;
  o.track_timeout = 5.0;
  const std::vector<double> rel{1.0};
  FuzzyAssociator fc(o, rel, 2);
  fc.process(0, 0, 0.0, 0.0, 0.0);
  fc.process(0, 0, 1.0, 10.0, 0.0);
  fc.process(0, 1, 9.0, 90.0, 0.0);
  EXPECT_TRUE(fc.process(0, 1, 10.0, 100.0, 0.0).new_track);  // track 0 last seen 9 s ago
  o.gate = -1;
  EXPECT_THROW(FuzzyAssociator(o, rel, 2), InputError);
  const std::vector<int32_t> s{0}, l{5};
  const std::vector<double> t{0.0}, x{0.0}, y{std::nan("")};
  const FuzzyAssociationOptions defaults;
  EXPECT_THROW(run_fuzzy_association({s, l, t, x, y}, rel, 2, defaults), InputError);
}
