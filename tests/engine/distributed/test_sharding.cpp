// The sharding layer of DESIGN §8 (engine/distributed/) and the sharded sparse S-D solve
// (engine/pipeline/sparse_sd_sharded.hpp), without MPI: the plain functions, and the collectives
// over an in-process stand-in for N ranks (each "rank" run in turn, the gather through a shared
// mailbox). The same code under mpirun is checked byte for byte by tests/mpi/ (MPI build only).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/sparse_3d_sharded.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/sparse_sd_sharded.hpp"
#include "engine/pipeline/workflow.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/studies/seed000/experiment_seed000.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

using distributed::ByteReader;
using distributed::Bytes;
using distributed::ByteWriter;

// Rank `r` of `n`: gather() leaves this rank's bytes in the mailbox; rank 0 (run last) returns them
// all. Good for exchanges that are one gather (sharded_items).
class MailboxRank final : public distributed::Communicator {
 public:
  MailboxRank(int r, int n, std::vector<Bytes>* box) : r_(r), n_(n), box_(box) {}
  int rank() const override { return r_; }
  int size() const override { return n_; }
  Bytes scatter(const std::vector<Bytes>&) override { throw std::logic_error("not in this test"); }
  std::vector<Bytes> gather(const Bytes& mine) override {
    (*box_)[r_] = mine;
    return r_ == 0 ? *box_ : std::vector<Bytes>{};
  }
  [[noreturn]] void abort(int) override { throw std::logic_error("abort"); }

 private:
  int r_, n_;
  std::vector<Bytes>* box_;
};

// Runs f(comm) as ranks n-1 … 1, then 0, and returns rank 0's answer.
template <class F>
auto over_ranks(int n, F f) {
  std::vector<Bytes> box(n);
  for (int r = n - 1; r >= 1; --r) {
    MailboxRank rank(r, n, &box);
    f(rank);
  }
  MailboxRank root(0, n, &box);
  return f(root);
}

TEST(ByteBuffer, RoundTripsValuesStringsAndVectors) {
  ByteWriter w;
  w.put<int32_t>(-7);
  w.put(std::string("seed000 run 3"));
  w.put(std::vector<double>{1.5, -0.0, 1e300});
  w.put_nested(std::vector<std::vector<int32_t>>{{1, 2}, {}, {3}});
  const Bytes b = w.take();
  ByteReader r(b);
  EXPECT_EQ(r.get<int32_t>(), -7);
  EXPECT_EQ(r.get_string(), "seed000 run 3");
  EXPECT_EQ(r.get_vector<double>(), (std::vector<double>{1.5, -0.0, 1e300}));
  EXPECT_EQ(r.get_nested<int32_t>(), (std::vector<std::vector<int32_t>>{{1, 2}, {}, {3}}));
  EXPECT_TRUE(r.done());
  EXPECT_THROW(r.get<int32_t>(), std::runtime_error);  // a short message is a bug, never silent
}

TEST(Sharding, RunsGoRoundRobinAndComponentsLongestFirst) {
  EXPECT_EQ(distributed::owner_of_item(0, 3), 0);
  EXPECT_EQ(distributed::owner_of_item(4, 3), 1);
  // LPT: 7 → 0, 5 → 1, 4 → 1 (load 5 < 7), 3 → 0, 1 → 1 (ties: lowest rank); makespan 10.
  const std::vector<double> cost{3, 7, 1, 5, 4};
  const auto owner = distributed::balance_by_cost(cost, 2);
  EXPECT_EQ(owner, (std::vector<int32_t>{0, 0, 1, 1, 1}));
  EXPECT_DOUBLE_EQ(distributed::makespan(cost, owner, 2), 10.0);
  EXPECT_EQ(distributed::balance_by_cost(cost, 2), owner);  // deterministic
  EXPECT_EQ(distributed::balance_by_cost({}, 4).size(), 0u);
}

std::vector<int64_t> items_over(int n, int64_t items) {
  return over_ranks(n, [&](distributed::Communicator& comm) {
    return distributed::sharded_items<int64_t>(
        comm, items, [](int64_t i) { return std::vector<int64_t>(i % 3, 10 * i); },
        [](int64_t i) { return "item " + std::to_string(i); },
        [](ByteWriter& w, const int64_t& x) { w.put(x); }, [](ByteReader& r) { return r.get<int64_t>(); });
  });
}

TEST(Sharding, ItemsComeBackInTheOrderOfOneProcess) {
  const auto one = items_over(1, 11);
  EXPECT_EQ(one.size(), 10u);
  for (int n : {2, 3, 4, 16}) EXPECT_EQ(items_over(n, 11), one) << n << " ranks";
}

TEST(Sharding, AFailingRankIsNamedWithItsShard) {
  // Item 4 of 3 ranks is rank 1's: rank 1 ends silently with exit status 2 (bad input), rank 0
  // throws the one message, naming the rank and the shard; rank 2 ends normally.
  std::vector<Bytes> box(3);
  auto run = [&](int r) {
    MailboxRank comm(r, 3, &box);
    return distributed::sharded_items<int>(
        comm, 6,
        [](int64_t i) -> std::vector<int> {
          if (i == 4) throw InputError("scenario: bad");
          return {1};
        },
        [](int64_t i) { return "run " + std::to_string(i); }, [](ByteWriter& w, const int& x) { w.put(x); },
        [](ByteReader& r) { return r.get<int>(); });
  };
  EXPECT_TRUE(run(2).empty());
  try {
    run(1);
    FAIL() << "rank 1 did not fail";
  } catch (const distributed::SilentExit& e) {
    EXPECT_EQ(e.code(), 2);
  }
  try {
    run(0);
    FAIL() << "rank 0 did not report";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rank 1, run 4: scenario: bad");
  }
}

TEST(Sharding, SeedZeroZeroZeroRowsDoNotDependOnTheRanks) {
  Seed000ExperimentOptions o;
  o.targets = {5};
  o.runs = 3;
  o.solvers = {"lr", "hopfield"};
  distributed::SingleProcessCommunicator one;
  const auto single = run_seed000_experiment(o, nullptr, one);
  ASSERT_EQ(single.size(), 2u * 3 * 2 * 2);
  const auto sharded = over_ranks(
      2, [&](distributed::Communicator& comm) { return run_seed000_experiment(o, nullptr, comm); });
  ASSERT_EQ(sharded.size(), single.size());
  for (std::size_t k = 0; k < single.size(); ++k) {
    EXPECT_EQ(sharded[k].run, single[k].run);
    EXPECT_EQ(sharded[k].correlated, single[k].correlated);
    EXPECT_EQ(sharded[k].form, single[k].form);
    EXPECT_EQ(sharded[k].solver, single[k].solver);
    EXPECT_EQ(sharded[k].objective, single[k].objective);  // bit for bit
    EXPECT_EQ(sharded[k].correct_rate, single[k].correct_rate);
    EXPECT_EQ(sharded[k].false_rate, single[k].false_rate);
  }
}

TEST(Sharding, CheckOnRootAloneIsTheCheck) {
  distributed::SingleProcessCommunicator one;
  EXPECT_THROW(distributed::check_on_root(one, [] { throw InputError("--output x/: is a directory"); }),
               InputError);
  EXPECT_NO_THROW(distributed::check_on_root(one, [] {}));
}

// The sparse S-D components planned for N ranks, encoded, solved part by part and merged, give
// the results of one process, and so the same record.
TEST(ShardedSparseSD, PartsSolvedApartMergeToTheSameRecord) {
  for (const char* name : {"recorded_3s", "recorded_5s"}) {
    const Scenario sc = load_scenario(name);
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
    SparseSDOptions so;
    const SparseSDProblem p = build_sparse_sd_problem(file, so);
    const bool all_pairs = so.pipeline.cost.form == CostForm::kAllPairs;
    const auto local =
        solve_sd_components(p, "lr+ls", nlohmann::json::object(), all_pairs, so.max_component_entries);
    for (int ranks : {1, 2, 3}) {
      const ComponentShards plan = plan_component_shards(p, so.max_component_entries, ranks);
      ASSERT_GT(plan.components.size(), 0u);
      const auto parts = encode_component_parts(p, plan, ranks, "lr+ls", nlohmann::json::object(), all_pairs,
                                                so.max_component_entries);
      ASSERT_EQ(static_cast<int>(parts.size()), ranks);
      std::vector<Bytes> solved;
      for (const auto& part : parts) solved.push_back(solve_component_part(part));
      const auto merged = merge_component_results(p, solved);
      ASSERT_EQ(merged.size(), local.size());
      for (std::size_t c = 0; c < local.size(); ++c) {
        EXPECT_EQ(merged[c].tuples, local[c].tuples) << name << " component " << c;
        EXPECT_EQ(merged[c].costs, local[c].costs);
        EXPECT_EQ(merged[c].objective, local[c].objective);
        EXPECT_EQ(merged[c].optimal, local[c].optimal);
      }
    }
    // A tiny tensor limit sends components to the merging fallback, which must travel too.
    const ComponentShards plan = plan_component_shards(p, 4, 2);
    const auto parts = encode_component_parts(p, plan, 2, "lr+ls", nlohmann::json::object(), all_pairs, 4);
    std::vector<Bytes> solved{solve_component_part(parts[1]), solve_component_part(parts[0])};
    const auto merged = merge_component_results(p, solved);
    const auto fallback = solve_sd_components(p, "lr+ls", nlohmann::json::object(), all_pairs, 4);
    for (std::size_t c = 0; c < fallback.size(); ++c) {
      EXPECT_EQ(merged[c].tuples, fallback[c].tuples);
      EXPECT_EQ(merged[c].fallback, fallback[c].fallback);
    }
  }
}

TEST(ShardedSparseSD, PlanBalancesTheEstimatedCost) {
  const Scenario sc = load_scenario("recorded_5s");
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const SparseSDProblem p = build_sparse_sd_problem(file, SparseSDOptions{});
  const ComponentShards plan = plan_component_shards(p, SparseSDOptions{}.max_component_entries, 2);
  double total = 0, largest = 0;
  for (double c : plan.cost) total += c, largest = std::max(largest, c);
  // LPT: within max(largest task, 4/3 of the even share) of the best.
  EXPECT_LE(distributed::makespan(plan.cost, plan.rank, 2), std::max(largest, total / 2) * 4.0 / 3.0 + 1e-9);
}

// The sparse 3-D (--sparse) components planned for N ranks, encoded, solved part by part (in any
// order) and decoded on "rank 0" give the record of one process, for both cost forms and a finite
// miss cost.
TEST(ShardedSparse3D, PartsSolvedApartDecodeToTheSameRecord) {
  for (const char* name : {"recorded_3s", "recorded_formation"})
    for (int variant = 0; variant < 3; ++variant) {
      const Scenario sc = load_scenario(name);
      const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
      SparsePipelineOptions so;
      if (variant == 1) so.pipeline.cost.form = CostForm::kChain;
      if (variant == 2) so.miss_cost = 50.f;
      const SparseAssociationProblem p = build_sparse_association_problem(file, so);
      for (const char* solver : {"lr", "exact"}) {
        const uint64_t seed = 11;
        const AssociationRecord one = solve_sparse_association(p, solver, nlohmann::json::object(), seed, so);
        for (int ranks : {1, 2, 3}) {
          const SparseComponentShards plan = plan_sparse_component_shards(p, so, ranks);
          ASSERT_GT(plan.components.size(), 1u);
          const auto parts =
              encode_sparse_component_parts(p, plan, ranks, solver, nlohmann::json::object(), seed, so);
          ASSERT_EQ(static_cast<int>(parts.size()), ranks);
          std::vector<Bytes> solved;
          for (int r = ranks - 1; r >= 0; --r) solved.push_back(solve_sparse_component_part(parts[r]));
          const auto solutions = merge_sparse_component_results(p, solved);
          const AssociationRecord rec =
              sparse_record_from_solutions(p, solutions, solver, seed, so, std::chrono::steady_clock::now());
          const std::string what = std::string(name) + " " + solver + " variant " + std::to_string(variant) +
                                   ", " + std::to_string(ranks) + " ranks";
          EXPECT_EQ(rec.tuples, one.tuples) << what;
          EXPECT_EQ(rec.cost, one.cost) << what;
          EXPECT_EQ(rec.objective, one.objective) << what;
          EXPECT_EQ(std::isnan(rec.lower_bound), std::isnan(one.lower_bound)) << what;
          if (!std::isnan(one.lower_bound)) {
            EXPECT_EQ(rec.lower_bound, one.lower_bound) << what;
          }
          EXPECT_EQ(rec.termination, one.termination) << what;
          EXPECT_EQ(rec.num_tuples(), one.num_tuples()) << what;
        }
      }
    }
  // A component over the tensor limit is refused by the plan, as by one process.
  const Scenario sc = load_scenario("recorded_formation");  // components of up to ~20 tracks
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  SparsePipelineOptions tiny;
  const SparseAssociationProblem p = build_sparse_association_problem(file, tiny);
  const SparseComponentShards plan = plan_sparse_component_shards(p, tiny, 2);
  const double largest = *std::max_element(plan.cost.begin(), plan.cost.end());
  ASSERT_GT(largest, 1.0);
  tiny.max_component_entries = static_cast<std::size_t>(largest) - 1;
  EXPECT_THROW(plan_sparse_component_shards(p, tiny, 2), InputError);
  EXPECT_THROW(solve_sparse_association(p, "lr", nlohmann::json::object(), 1, tiny), InputError);
}

TEST(ShardedSparse3D, PlanBalancesTheDenseSubTensorEntries) {
  const Scenario sc = load_scenario("recorded_formation");
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const SparsePipelineOptions so;
  const SparseAssociationProblem p = build_sparse_association_problem(file, so);
  const SparseComponentShards plan = plan_sparse_component_shards(p, so, 2);
  double total = 0, largest = 0;
  for (std::size_t k = 0; k < plan.components.size(); ++k) {
    const auto m = sparse_component_matrices(p, plan.components[k], so);
    EXPECT_EQ(plan.cost[k], static_cast<double>(m.n[0]) * m.n[1] * m.n[2]);
    total += plan.cost[k], largest = std::max(largest, plan.cost[k]);
  }
  EXPECT_LE(distributed::makespan(plan.cost, plan.rank, 2), std::max(largest, total / 2) * 4.0 / 3.0 + 1e-9);
}

}  // namespace
}  // namespace trackassoc
