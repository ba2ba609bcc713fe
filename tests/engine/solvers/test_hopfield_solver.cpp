// The Hopfield solvers end to end (kernels/hopfield/hopfield.hpp, engine/solvers/hopfield_json.hpp): valid
// output whose objective is its recomputed cost, determinism across thread counts, optimality on small
// instances solved by brute force, and option errors.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "engine/solvers/hopfield_json.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "kernels/hopfield/hopfield_discrete.hpp"
#include "tests/support/hopfield_instances.hpp"

namespace trackassoc {
namespace {

GeometricInstance instance(int32_t n, double noise, uint64_t k) {
  GeometricInstanceOptions o;
  o.n = n;
  o.noise_to_spacing = noise;
  return make_geometric_instance(o, 2024, k);
}

// Optimum of an n×n×n instance by enumerating both permutations (n ≤ 7).
double brute_force_optimum(const CostTensor3& b) {
  const int32_t n = b.n1;
  std::vector<int32_t> pj(n), pk(n);
  std::iota(pj.begin(), pj.end(), 0);
  double best = INFINITY;
  do {
    std::iota(pk.begin(), pk.end(), 0);
    do {
      double s = 0;
      for (int32_t i = 0; i < n; ++i) s += b.at(i, pj[i], pk[i]);
      best = std::min(best, s);
    } while (std::next_permutation(pk.begin(), pk.end()));
  } while (std::next_permutation(pj.begin(), pj.end()));
  return best;
}

struct Config {
  const char* name;
  HopfieldOptions o;
};

std::vector<Config> all_configs() {
  std::vector<Config> v;
  for (HopfieldNetwork n : {HopfieldNetwork::kDiscrete, HopfieldNetwork::kContinuous})
    for (HopfieldSchedule s :
         {HopfieldSchedule::kSync, HopfieldSchedule::kAsync, HopfieldSchedule::kDiagonal})
      for (HopfieldEnergy e : {HopfieldEnergy::kFullPlane, HopfieldEnergy::kPrinted}) {
        const bool continuous = n == HopfieldNetwork::kContinuous;
        if (continuous && s != HopfieldSchedule::kAsync) continue;  // one continuous configuration
        if (e == HopfieldEnergy::kPrinted && (s == HopfieldSchedule::kDiagonal || continuous)) continue;
        HopfieldOptions o;
        o.network = n;
        o.schedule = s;
        o.energy = e;
        o.restarts = 3;
        v.push_back({hopfield_schedule_label(o), o});
      }
  for (HopfieldInit init : {HopfieldInit::kZero, HopfieldInit::kRandom, HopfieldInit::kGreedy}) {
    HopfieldOptions o;
    o.init = init;
    o.order = HopfieldOrder::kRandom;
    o.anneal_E_factor = 3.0;
    o.restarts = 2;
    v.push_back({enum_name(init), o});
  }
  HopfieldOptions g;
  g.temperature = 0.2;
  g.restarts = 2;
  v.push_back({"glauber", g});
  HopfieldOptions d;
  d.schedule = HopfieldSchedule::kSync;
  d.damping = 0.3;
  d.init = HopfieldInit::kRandom;
  v.push_back({"sync-damped", d});
  v.push_back({"paper", hopfield_preset("hopfield-paper")});
  HopfieldOptions ca;
  ca.network = HopfieldNetwork::kContinuous;
  ca.continuous_async = true;
  ca.restarts = 2;
  v.push_back({"continuous-async", ca});
  return v;
}

TEST(HopfieldSolver, ReturnsValidAssignmentsWithRecomputedObjective) {
  std::vector<CostTensor3> tensors = {instance(8, 0.5, 1).cost, instance(5, 1.0, 2).cost};
  CostTensor3 rect(4, 5, 6);
  CounterRng rng(3);
  for (auto& b : rect.cost) b = static_cast<float>(rng.uniform(0, 10));
  tensors.push_back(rect);
  for (const auto& cfg : all_configs())
    for (const auto& t : tensors) {
      const HopfieldResult r = solve_hopfield(t, cfg.o, 11);
      EXPECT_TRUE(is_valid_assignment(t, r.solution.tuples)) << cfg.name;
      EXPECT_TRUE(r.solution.summary.feasible) << cfg.name;
      EXPECT_EQ(r.solution.summary.objective, assignment_cost(t, r.solution.tuples)) << cfg.name;
      ASSERT_EQ(static_cast<int32_t>(r.restarts.size()), cfg.o.restarts);
      double best = INFINITY;
      for (const auto& rr : r.restarts) best = std::min(best, rr.objective);
      EXPECT_EQ(best, r.solution.summary.objective) << cfg.name;
      // The validity rate is the share of restarts whose raw state was feasible, counted here.
      int valid = 0;
      for (const auto& rr : r.restarts) valid += rr.raw_feasible;
      EXPECT_DOUBLE_EQ(r.raw_validity_rate, double(valid) / double(r.restarts.size())) << cfg.name;
    }
}

TEST(HopfieldSolver, RawValidityMatchesTheNetworkState) {
  // With every valid assignment a fixed point, a greedy start stays put: raw valid, zero flips.
  const GeometricInstance g = instance(10, 0.5, 3);
  HopfieldOptions o;
  o.init = HopfieldInit::kGreedy;
  o.restarts = 1;
  const HopfieldResult r = solve_hopfield(g.cost, o, 1);
  EXPECT_EQ(r.raw_validity_rate, 1.0);
  EXPECT_EQ(r.restarts[0].sweeps, 1);
  EXPECT_EQ(r.restarts[0].termination, Termination::kConverged);
  // From the empty state the paper's network (printed energy) ends invalid on this instance or
  // valid; either way the reported rate is the share of valid raw states.
  const HopfieldResult p = solve_hopfield(g.cost, hopfield_preset("hopfield-paper"), 1);
  EXPECT_TRUE(p.raw_validity_rate == 0.0 || p.raw_validity_rate == 1.0);
}

TEST(HopfieldSolver, IdenticalForOneAndTwoThreads) {
  const GeometricInstance g = instance(12, 0.6, 4);
  for (auto cfg : all_configs()) {
    cfg.o.restarts = 4;
    cfg.o.trace = true;
    HopfieldResult r1, r2;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
      r1 = solve_hopfield(g.cost, cfg.o, 99);
    }
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
      r2 = solve_hopfield(g.cost, cfg.o, 99);
    }
    EXPECT_EQ(r1.solution.tuples, r2.solution.tuples) << cfg.name;
    ASSERT_EQ(r1.restarts.size(), r2.restarts.size());
    for (std::size_t i = 0; i < r1.restarts.size(); ++i) {
      EXPECT_EQ(r1.restarts[i].energy, r2.restarts[i].energy) << cfg.name;
      EXPECT_EQ(r1.restarts[i].sweeps, r2.restarts[i].sweeps) << cfg.name;
      EXPECT_EQ(r1.restarts[i].energy_trace, r2.restarts[i].energy_trace) << cfg.name;
    }
  }
}

TEST(HopfieldSolver, DefaultFindsBruteForceOptimumOnSmallInstances) {
  int optimal = 0, total = 0;
  for (uint64_t k = 0; k < 12; ++k) {
    const GeometricInstance g = instance(6, 0.4, 100 + k);
    const double opt = brute_force_optimum(g.cost);
    const HopfieldResult r = solve_hopfield(g.cost, HopfieldOptions{}, 5);
    EXPECT_GE(r.solution.summary.objective, opt - 1e-3);
    optimal += r.solution.summary.objective <= opt + 1e-3;
    ++total;
  }
  EXPECT_GE(optimal, total - 1) << "default hopfield optimal on " << optimal << "/" << total;
}

// On an easy instance (noise 0.1 of the target spacing) the true association is (near) optimal:
// the solvers must find an assignment at least as cheap, and agree with the truth on almost all
// tuples.
// On an easy geometric instance (n = 30, noise 0.1 of the spacing) the networks are heuristics:
// every valid assignment is a fixed point, so a restart ends at the assignment its mean-field start
// leads to. Measured over seeds 1–12: at most 4.0 % above the truth's cost with at least 27 of the
// 30 true triples, for both hopfield and chnn; with --polish (LAP local search on every restart) at
// or below the truth's cost every time. (Session 3 found that the earlier form of this test, one
// seed and "matches the truth", passed by luck: about a third of the seeds end a few % above.)
TEST(HopfieldSolver, EasyInstanceNearTheTruthAndAtItWithPolish) {
  const GeometricInstance g = instance(30, 0.1, 7);
  const double truth_cost = assignment_cost(g.cost, g.truth);
  for (const char* name : {"hopfield", "chnn"})
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      const Solution3 s = solve_hopfield_json(name, g.cost, nlohmann::json::object(), seed);
      EXPECT_LE(s.summary.objective, 1.05 * truth_cost) << name << " seed " << seed;
      int same = 0;
      for (const auto& t : s.tuples) same += std::find(g.truth.begin(), g.truth.end(), t) != g.truth.end();
      EXPECT_GE(same, 26) << name << " seed " << seed;
      const Solution3 p = solve_hopfield_json(name, g.cost, nlohmann::json{{"polish", true}}, seed);
      EXPECT_LE(p.summary.objective, truth_cost + 1e-3) << name << " +polish, seed " << seed;
    }
}

// Cost vectors for the radix sort: random values with many ties, negative values, ±0, infinities
// and a subnormal (every digit pass), one value for all (every pass skipped), values that differ
// only in the low 11 bits (one pass) or the low 22 bits (two passes). K = 60000 gives 3 chunks.
std::vector<std::vector<float>> cost_vectors_for_the_sort() {
  CounterRng rng(8, 3);
  std::vector<std::vector<float>> out;
  for (std::size_t K : {0u, 1u, 2u, 7u, 1000u, 70000u}) {
    std::vector<float> c(K);
    for (auto& x : c) {
      const double u = rng.uniform();
      x = u < 0.2 ? static_cast<float>(static_cast<int>(rng.uniform() * 5))  // many ties
                  : static_cast<float>(rng.uniform(-3.0, 3.0));
    }
    if (K >= 7) {
      c[1] = -0.f;
      c[2] = 0.f;
      c[3] = INFINITY;
      c[4] = -INFINITY;
      c[5] = 1e-40f;  // subnormal
    }
    out.push_back(c);
  }
  out.push_back(std::vector<float>(60000, 0.25f));
  for (uint32_t low_bits : {11u, 22u}) {
    std::vector<float> c(60000);
    for (auto& x : c) {
      const uint32_t bits = 0x3e800000u + static_cast<uint32_t>(rng.uniform_int(std::size_t{1} << low_bits));
      std::memcpy(&x, &bits, sizeof x);
    }
    out.push_back(c);
  }
  return out;
}

// The radix-sorted cost order equals std::stable_sort by value (ties in index order).
TEST(HopfieldSolver, AscendingCostOrderEqualsStableSort) {
  for (const std::vector<float>& c : cost_vectors_for_the_sort()) {
    std::vector<uint32_t> expected(c.size());
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(), [&](uint32_t x, uint32_t y) { return c[x] < c[y]; });
    EXPECT_EQ(ascending_cost_order(c), expected) << c.size();
  }
}

TEST(HopfieldSolver, EmptyAndTinyInstances) {
  EXPECT_TRUE(solve_hopfield(CostTensor3(0, 3, 3), HopfieldOptions{}, 1).solution.tuples.empty());
  CostTensor3 one(1, 1, 1, 5.f);
  const HopfieldResult r = solve_hopfield(one, HopfieldOptions{}, 1);
  ASSERT_EQ(r.solution.tuples.size(), 1u);
  EXPECT_EQ(r.solution.summary.objective, 5.0);
  CostTensor3 bad(2, 2, 2, 1.f);
  bad.cost[3] = NAN;
  EXPECT_THROW(solve_hopfield(bad, HopfieldOptions{}, 1), InputError);
}

TEST(HopfieldSolver, RegistryEntriesAndOptionErrors) {
  const GeometricInstance g = instance(8, 0.5, 9);
  for (const char* name : {"hopfield", "hopfield-paper", "chnn"}) {
    const SolverEntry& e = find_solver(name);
    const Solution3 s = e.solve(g.cost, nlohmann::json{{"restarts", 2}, {"trace", true}}, 1);
    EXPECT_TRUE(is_valid_assignment(g.cost, s.tuples)) << name;
    EXPECT_EQ(s.energy_rows, 2) << name;
    EXPECT_GT(s.energy_cols, 0) << name;
    EXPECT_EQ(s.energy_trace.size(), static_cast<std::size_t>(s.energy_rows) * s.energy_cols);
  }
  const SolverEntry& h = find_solver("hopfield");
  EXPECT_NO_THROW(h.solve(g.cost, nlohmann::json{{"schedule", "diagonal"}, {"init", "greedy"}}, 1));
  EXPECT_NO_THROW(h.solve(g.cost, nlohmann::json{{"A", 2.0}, {"E", 1.0}, {"energy", "printed"}}, 1));
  auto expect_error = [&](const nlohmann::json& o, const std::string& needle) {
    try {
      h.solve(g.cost, o, 1);
      ADD_FAILURE() << "no error for " << o.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error({{"restarts", 0}}, "restarts");
  expect_error({{"restarts", "many"}}, "restarts");
  expect_error({{"schedule", "chaotic"}}, "schedule");
  expect_error({{"bogus", 1}}, "bogus");
  expect_error({{"damping", 1.5}}, "damping");
  expect_error({{"schedule", "diagonal"}, {"D", 1.0}}, "D = 0");
  expect_error({{"schedule", "continuous"}}, "solver 'chnn'");
  expect_error(nlohmann::json::array(), "JSON object");
  const SolverEntry& chnn = find_solver("chnn");
  EXPECT_THROW(chnn.solve(g.cost, nlohmann::json{{"energy", "printed"}}, 1), InputError);  // full plane only
  try {
    chnn.solve(g.cost, nlohmann::json{{"schedule", "diagonal"}}, 1);
    ADD_FAILURE() << "no error for chnn + diagonal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("discrete network (solver 'hopfield')"), std::string::npos)
        << e.what();
  }
}

// `schedule` on chnn picks the order of its Euler steps and keeps the network continuous: "async"
// is exactly the continuous network with async steps, "sync" and "continuous" the preset itself.
TEST(HopfieldSolver, ChnnScheduleSelectsTheEulerStepOrder) {
  const GeometricInstance g = instance(8, 0.5, 11);
  HopfieldOptions async_options = hopfield_preset("chnn");
  async_options.continuous_async = true;
  async_options.restarts = 2;
  HopfieldOptions sync_options = async_options;
  sync_options.continuous_async = false;
  const HopfieldResult a = solve_hopfield(g.cost, async_options, 4),
                       s = solve_hopfield(g.cost, sync_options, 4);
  auto expect_same = [](const Solution3& x, const HopfieldResult& y, const char* what) {
    EXPECT_EQ(x.tuples, y.solution.tuples) << what;
    ASSERT_EQ(x.restarts.sweeps.size(), y.restarts.size()) << what;
    for (std::size_t r = 0; r < y.restarts.size(); ++r) {
      EXPECT_EQ(x.restarts.sweeps[r], y.restarts[r].sweeps) << what << " restart " << r;
      EXPECT_EQ(x.restarts.mean_field_steps[r], 0) << what;  // continuous: no discrete phase
    }
  };
  expect_same(solve_hopfield_json("chnn", g.cost, {{"schedule", "async"}, {"restarts", 2}}, 4), a, "async");
  expect_same(solve_hopfield_json("chnn", g.cost, {{"schedule", "sync"}, {"restarts", 2}}, 4), s, "sync");
  expect_same(solve_hopfield_json("chnn", g.cost, {{"schedule", "continuous"}, {"restarts", 2}}, 4), s,
              "continuous");
}

}  // namespace
}  // namespace trackassoc
