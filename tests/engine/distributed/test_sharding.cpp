// The sharding layer of docs/design.md §8 (engine/distributed/) and the sharded component solves of
// the default path and of --sparse, without MPI: the plain functions, and the collectives
// over an in-process stand-in for N ranks (each "rank" run in turn, the gather through a shared
// mailbox). The same code under mpirun is checked byte for byte by tests/mpi/ (MPI build only).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "engine/distributed/shard_items.hpp"
#include "engine/distributed/sharding.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/sparse_sd_components.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/seed000/experiment_seed000.hpp"
#include "engine/studies/seed001/experiment_seed001.hpp"
#include "engine/studies/seed002/experiment_seed002.hpp"
#include "engine/studies/seed003/experiment_seed003.hpp"
#include "io/siamese_model_file.hpp"
#include "kernels/core/error.hpp"
#include "tests/support/thread_ranks.hpp"

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
  const Bytes b = w.take();
  ByteReader r(b);
  EXPECT_EQ(r.get<int32_t>(), -7);
  EXPECT_EQ(r.get_string(), "seed000 run 3");
  EXPECT_EQ(r.get_vector<double>(), (std::vector<double>{1.5, -0.0, 1e300}));
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
        [](int64_t i) { return "item " + std::to_string(i); });
  });
}

TEST(Sharding, ItemsComeBackInTheOrderOfOneProcess) {
  const auto one = items_over(1, 11);
  EXPECT_EQ(one.size(), 10u);
  for (int n : {2, 3, 4, 16}) EXPECT_EQ(items_over(n, 11), one) << n << " ranks";
}

TEST(Sharding, ParallelItemsComeBackInTheOrderOfOneProcess) {
  auto over = [](int n, bool parallel) {
    return over_ranks(n, [&](distributed::Communicator& comm) {
      return distributed::sharded_items<int64_t>(
          comm, 23, [](int64_t i) { return std::vector<int64_t>(i % 3, 10 * i); },
          [](int64_t i) { return "item " + std::to_string(i); }, parallel);
    });
  };
  const auto one = over(1, false);
  for (int n : {1, 2, 3, 5}) EXPECT_EQ(over(n, true), one) << n << " ranks";
}

TEST(Sharding, AFailingParallelItemIsNamedFirstInItemOrder) {
  // Rank 1 of 2 holds items 1, 3, 5: 3 and 5 fail, 3 is named, and bad input stays bad input.
  std::vector<Bytes> box(2);
  auto run = [&](int r) {
    MailboxRank comm(r, 2, &box);
    return distributed::sharded_items<int>(
        comm, 6,
        [](int64_t i) -> std::vector<int> {
          if (i == 3 || i == 5) throw InputError("run " + std::to_string(i) + " bad");
          return {1};
        },
        [](int64_t i) { return "run " + std::to_string(i); }, /*parallel=*/true);
  };
  EXPECT_THROW(run(1), distributed::SilentExit);
  try {
    run(0);
    FAIL() << "rank 0 did not report";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rank 1, run 3: run 3 bad");
  }
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
        [](int64_t i) { return "run " + std::to_string(i); });
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

// The Monte Carlo studies seed001–seed003 over 1, 2 and 3 ranks: rank 0 gets the figures of one
// process bit for bit (the MPI build checks the files and tables, tests/mpi/mpi_case.sh).
TEST(Sharding, SeedZeroZeroOneResultsDoNotDependOnTheRanks) {
  Seed001Options o;
  o.runs = 5;
  o.duration = 40.0;
  Seed001Options literal = o;
  literal.bearing_reading = BearingReading::kLiteral;
  const Seed001Result single = run_seed001(o), single_literal = run_seed001(literal);
  for (int n : {2, 3}) {
    const auto both = over_ranks(n, [&](distributed::Communicator& comm) {
      return run_seed001_readings({o, literal}, comm);
    });
    ASSERT_EQ(both.size(), 2u);
    for (const auto& [one, many] : {std::pair{&single, &both[0]}, std::pair{&single_literal, &both[1]}})
      for (bool ftaa : {false, true}) {
        const Seed001MethodResult& a = ftaa ? one->ftaa : one->fuzzy;
        const Seed001MethodResult& b = ftaa ? many->ftaa : many->fuzzy;
        for (int t = 0; t < 2; ++t) {
          EXPECT_EQ(a.mean_rmse[t], b.mean_rmse[t]) << n << " ranks";
          EXPECT_EQ(0, std::memcmp(a.rmse[t].data(), b.rmse[t].data(), a.rmse[t].size() * sizeof(double)));
        }
        EXPECT_EQ(a.correct_rate, b.correct_rate);
        EXPECT_EQ(a.system_tracks_per_run, b.system_tracks_per_run);
        EXPECT_EQ(a.decisions_per_run, b.decisions_per_run);
      }
    EXPECT_EQ(both[0].example.tracks.size(), single.example.tracks.size());  // run 0, on rank 0
    EXPECT_EQ(both[0].example.metrics.size(), single.example.metrics.size());
  }
}

TEST(Sharding, SeedZeroZeroTwoMotionsDoNotDependOnTheRanks) {
  // The table's setting and two of the sweep's in one exchange (the stand-in holds one gather; the
  // table then the sweep, two gathers, are checked under mpirun).
  Seed002Options o;
  o.runs = 4;
  const std::vector<Seed002Models> settings{
      o.models, {.ca_sigma = 1.0, .cs_a_max = 100.0}, {.ca_sigma = 1.0, .cs_a_max = 200.0}};
  const BpNetwork net = trained_cs_network(nullptr);
  const Seed002Result single = run_seed002(o);
  std::vector<Seed002Motion> expected = single.motions;
  for (std::size_t k = 1; k < settings.size(); ++k)
    for (int m = 0; m < 4; ++m) expected.push_back(run_seed002_motion(m, o, settings[k], net));
  for (int n : {2, 3, 5}) {
    const auto many = over_ranks(
        n, [&](distributed::Communicator& comm) { return run_seed002_motions(o, settings, net, comm); });
    ASSERT_EQ(many.size(), expected.size());
    for (std::size_t k = 0; k < many.size(); ++k) {
      const Seed002Motion &a = expected[k], &b = many[k];
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.ratio, b.ratio) << n << " ranks, item " << k;
      EXPECT_EQ(a.mean_ca, b.mean_ca);
      EXPECT_EQ(a.imm_prob_cs, b.imm_prob_cs);
      for (int q = 0; q < 3; ++q) EXPECT_EQ(a.rmse_imm[q], b.rmse_imm[q]);
    }
  }
}

TEST(Sharding, SeedZeroZeroThreeScoresDoNotDependOnTheRanks) {
  const SiameseModel<float> model =
      read_siamese_model(TRACKASSOC_SOURCE_DIR "/data/models/siamese_seed003.h5").model;
  Seed003ExperimentOptions o;
  o.runs = 3;
  o.densities = {5, 10};
  distributed::SingleProcessCommunicator one;
  const Seed003ExperimentResult single = run_seed003_experiment(model, o, {}, one);
  const Seed003ExperimentResult many = over_ranks(
      3, [&](distributed::Communicator& comm) { return run_seed003_experiment(model, o, {}, comm); });
  ASSERT_EQ(many.methods.size(), single.methods.size());
  for (std::size_t m = 0; m < single.methods.size(); ++m) {
    EXPECT_EQ(many.methods[m].method, single.methods[m].method);
    for (auto score :
         {&Seed003MethodCurve::accuracy, &Seed003MethodCurve::recall, &Seed003MethodCurve::precision})
      EXPECT_EQ(many.methods[m].*score, single.methods[m].*score) << single.methods[m].method;
  }
}

TEST(Sharding, CheckOnRootAloneIsTheCheck) {
  distributed::SingleProcessCommunicator one;
  EXPECT_THROW(distributed::check_on_root(one, [] { throw InputError("--output x/: is a directory"); }),
               InputError);
  EXPECT_NO_THROW(distributed::check_on_root(one, [] {}));
}

// A toy job for the generic item sharding: item k is a list of numbers, its result their sum and
// its largest, solved with a header shared by the part (a scale).
struct ToyHeader {
  double scale = 1.0;
  std::string tag;
};
struct ToyItem {
  int64_t label = 0;
  std::vector<double> values;
};
struct ToyResult {
  double sum = 0.0, largest = 0.0;
  std::string tag;
};

constexpr auto wire_codec(std::type_identity<ToyHeader>) {
  return distributed::codec<ToyHeader>("toy header", &ToyHeader::scale, &ToyHeader::tag);
}
constexpr auto wire_codec(std::type_identity<ToyItem>) {
  return distributed::codec<ToyItem>("toy item", &ToyItem::label, &ToyItem::values);
}
constexpr auto wire_codec(std::type_identity<ToyResult>) {
  return distributed::codec<ToyResult>("toy result", &ToyResult::sum, &ToyResult::largest, &ToyResult::tag);
}

constexpr distributed::ItemJob<ToyHeader, ToyItem, ToyResult> kToyJob{
    "item", "values", [](const ToyItem& x) { return x.values.size(); },
    [](const ToyHeader& h, const ToyItem& x) {
      if (x.label < 0) throw InputError("toy item " + std::to_string(x.label) + " is negative");
      ToyResult r;
      r.tag = h.tag + std::to_string(x.label);
      for (double v : x.values) r.sum += h.scale * v, r.largest = std::max(r.largest, h.scale * v);
      return r;
    }};

ToyItem toy_item(std::size_t k) {
  ToyItem x;
  x.label = static_cast<int64_t>(k) * 10;
  for (std::size_t j = 0; j <= k % 4; ++j) x.values.push_back(0.5 * static_cast<double>(k + j));
  return x;
}

TEST(ShardItems, ResultsAtNRanksAreThoseOfOneProcessInPlanOrder) {
  const std::size_t n = 13;
  std::vector<int64_t> id;
  std::vector<double> cost;
  for (std::size_t k = 0; k < n; ++k)
    id.push_back(static_cast<int64_t>(100 + k)), cost.push_back(static_cast<double>(k % 5));
  const ToyHeader header{2.0, "x"};
  for (int ranks : {1, 2, 3, 5}) {
    const auto results = testing::over_thread_ranks(ranks, [&](distributed::Communicator& comm) {
      if (!comm.root()) {
        distributed::serve_items(comm, kToyJob);
        return std::vector<ToyResult>{};
      }
      return distributed::shard_items(comm, kToyJob, "toy items", header, id, cost, toy_item);
    });
    ASSERT_EQ(results.size(), n) << ranks << " ranks";
    for (std::size_t k = 0; k < n; ++k) {
      // Worked out here: 2 × 0.5 × Σ_{j ≤ k mod 4} (k + j), the largest term 2 × 0.5 × (k + k mod 4).
      double sum = 0.0;
      for (std::size_t j = 0; j <= k % 4; ++j) sum += static_cast<double>(k + j);
      EXPECT_EQ(results[k].sum, sum) << ranks << " ranks, item " << k;
      EXPECT_EQ(results[k].largest, static_cast<double>(k + k % 4));
      EXPECT_EQ(results[k].tag, std::string("x").append(std::to_string(10 * k)));
    }
  }
}

TEST(ShardItems, AFailingItemIsNamedWithItsRank) {
  // Items 0..5 of equal cost over 2 ranks (LPT: even items to rank 0, odd to rank 1); item 3 fails.
  const std::vector<int64_t> id{0, 1, 2, 3, 4, 5};
  const std::vector<double> cost(6, 1.0);
  auto item = [](std::size_t k) {
    ToyItem x = toy_item(k);
    if (k == 3) x.label = -7;
    return x;
  };
  ASSERT_EQ(distributed::balance_by_cost(cost, 2)[3], 1);
  std::vector<std::exception_ptr> failures;
  try {
    testing::over_thread_ranks(
        2,
        [&](distributed::Communicator& comm) {
          if (!comm.root()) {
            distributed::serve_items(comm, kToyJob);
            return std::vector<ToyResult>{};
          }
          return distributed::shard_items(comm, kToyJob, "toy items", ToyHeader{}, id, cost, item);
        },
        &failures);
    FAIL() << "rank 0 did not report";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rank 1, item 3 (4 values): toy item -7 is negative");
  }
  ASSERT_TRUE(failures[1]);
  try {
    std::rethrow_exception(failures[1]);
  } catch (const distributed::SilentExit& e) {
    EXPECT_EQ(e.code(), 2);  // bad input stays bad input on the failing rank too
  }
}

// The default path's components solved over N fake ranks give the results of one process, with
// the listed-tuple solve travelling too (a tiny tensor limit).
TEST(ShardedSparseSD, ComponentsOverRanksAreThoseOfOneProcess) {
  for (const char* name : {"recorded_3s", "recorded_5s"}) {
    const Scenario sc = load_scenario(name);
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
    SparseSDOptions so;
    const SparseSDProblem p = build_sparse_sd_problem(file, so);
    const bool all_pairs = so.pipeline.cost.form == CostForm::kAllPairs;
    for (std::size_t max_entries : {so.max_component_entries, std::size_t{4}}) {
      const auto local = solve_sd_components(p, "lr+ls", nlohmann::json::object(), all_pairs, max_entries);
      for (int ranks : {2, 3}) {
        const auto merged = testing::over_thread_ranks(ranks, [&](distributed::Communicator& comm) {
          if (!comm.root()) {
            serve_sd_components(comm);
            return std::vector<SDComponentResult>{};
          }
          return solve_sd_components_sharded(comm, p, "lr+ls", nlohmann::json::object(), all_pairs,
                                             max_entries);
        });
        ASSERT_EQ(merged.size(), local.size());
        int listed = 0;
        for (std::size_t c = 0; c < local.size(); ++c) {
          EXPECT_EQ(merged[c].tuples, local[c].tuples) << name << " component " << c;
          EXPECT_EQ(merged[c].costs, local[c].costs);
          EXPECT_EQ(merged[c].objective, local[c].objective);
          EXPECT_EQ(merged[c].fallback, local[c].fallback);
          EXPECT_EQ(merged[c].termination, local[c].termination);
          EXPECT_EQ(merged[c].entries, local[c].entries);
          EXPECT_EQ(merged[c].listed_tuples, local[c].listed_tuples);
          EXPECT_EQ(merged[c].lower_bound, local[c].lower_bound);
          listed += merged[c].listed_tuples > 0;
        }
        if (max_entries == 4) {
          EXPECT_GT(listed, 0) << name;  // the solve over listed tuples was exercised
        }
      }
    }
  }
}

// The default path's build over N fake ranks (each sensor pair's prune and statistic solved where
// it lands, engine/pipeline/pair_statistics_sharded.hpp) gives the problem of one process, bit for
// bit: the candidate counts, every gated pair with its λ, degrees of freedom and link cost, and the
// components.
TEST(ShardedSparseSD, GatedStatisticsOverRanksAreThoseOfOneProcess) {
  for (const char* name : {"recorded_5s", "recorded_dense"}) {
    const Scenario sc = load_scenario(name);
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
    const SparseSDProblem local = build_sparse_sd_problem(file, SparseSDOptions{});
    for (int ranks : {2, 3}) {
      uint64_t sent = 0;  // rank 0's bytes out: the items of the sensor pairs
      const auto built = testing::over_thread_ranks(ranks, [&](distributed::Communicator& comm) {
        if (!comm.root()) {
          serve_sd_components(comm);
          return SparseSDProblem{};
        }
        SparseSDOptions so;
        so.ranks = &comm;
        comm.set_ranks_waiting(true);
        SparseSDProblem p = build_sparse_sd_problem(file, so);
        sent = comm.stats().bytes_sent;
        distributed::end_items(comm);
        return p;
      });
      EXPECT_GT(sent, 10000u) << name;  // the sensor pairs did travel
      ASSERT_EQ(built.pairs.size(), local.pairs.size());
      std::size_t gated = 0;
      for (std::size_t slot = 0; slot < local.pairs.size(); ++slot) {
        const SparsePairStatistic &x = built.pairs[slot], &y = local.pairs[slot];
        EXPECT_EQ(built.candidate_pairs[slot], local.candidate_pairs[slot]) << name << " slot " << slot;
        EXPECT_EQ(x.n_a, y.n_a);
        EXPECT_EQ(x.n_b, y.n_b);
        EXPECT_EQ(x.a, y.a) << name << " slot " << slot;
        EXPECT_EQ(x.b, y.b);
        EXPECT_EQ(x.lambda, y.lambda);  // bit for bit
        EXPECT_EQ(x.dof, y.dof);
        EXPECT_EQ(built.link[slot], local.link[slot]);
        gated += y.size();
      }
      EXPECT_GT(gated, 100u) << name;  // the statistics were exercised
      EXPECT_EQ(built.components.count, local.components.count);
      EXPECT_EQ(built.components.nodes, local.components.nodes);
      // (bytes_held is not compared: it is the larger of the stages' counts and the process's
      // resident set, io/memory_budget.hpp, which differs between two builds in one process.)
    }
  }
}

TEST(ShardedSparseSD, PlanBalancesTheEstimatedCost) {
  const Scenario sc = load_scenario("recorded_5s");
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  const SparseSDProblem p = build_sparse_sd_problem(file, SparseSDOptions{});
  const SDComponentCosts plan = sd_component_costs(p, SparseSDOptions{}.max_component_entries);
  ASSERT_GT(plan.cost.size(), 1u);
  double total = 0, largest = 0;
  for (std::size_t k = 0; k < plan.cost.size(); ++k) {
    EXPECT_EQ(plan.cost[k], sd_component_view(p, static_cast<int32_t>(plan.component[k])).entries());
    total += plan.cost[k], largest = std::max(largest, plan.cost[k]);
  }
  // LPT: within max(largest task, 4/3 of the even share) of the best.
  const auto rank = distributed::balance_by_cost(plan.cost, 2);
  EXPECT_LE(distributed::makespan(plan.cost, rank, 2), std::max(largest, total / 2) * 4.0 / 3.0 + 1e-9);
}

// The --sparse (3-D) components over N fake ranks, decoded on rank 0, give the record of one
// process, for both cost forms and a finite miss cost.
TEST(ShardedSparse3D, ComponentsOverRanksDecodeToTheSameRecord) {
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
        for (int ranks : {2, 3}) {
          const auto solutions = testing::over_thread_ranks(ranks, [&](distributed::Communicator& comm) {
            if (!comm.root()) {
              serve_sparse_components(comm);
              return std::vector<SparseComponentSolution>{};
            }
            return solve_sparse_components_sharded(comm, p, solver, nlohmann::json::object(), seed, so);
          });
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
}

TEST(ShardedSparse3D, PlanCountsTheDenseSubTensorEntriesAndRefusesAnOversizedComponent) {
  const Scenario sc = load_scenario("recorded_formation");  // components of up to ~20 tracks
  const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
  SparsePipelineOptions so;
  const SparseAssociationProblem p = build_sparse_association_problem(file, so);
  const SparseComponentCosts plan = sparse_component_costs(p, so);
  double total = 0, largest = 0;
  for (std::size_t k = 0; k < plan.component.size(); ++k) {
    const auto m = sparse_component_matrices(p, static_cast<int32_t>(plan.component[k]), so);
    EXPECT_EQ(plan.cost[k], static_cast<double>(m.n[0]) * m.n[1] * m.n[2]);
    total += plan.cost[k], largest = std::max(largest, plan.cost[k]);
  }
  const auto rank = distributed::balance_by_cost(plan.cost, 2);
  EXPECT_LE(distributed::makespan(plan.cost, rank, 2), std::max(largest, total / 2) * 4.0 / 3.0 + 1e-9);
  // A component over the tensor limit is refused by the plan, as by one process.
  ASSERT_GT(largest, 1.0);
  so.max_component_entries = static_cast<std::size_t>(largest) - 1;
  EXPECT_THROW(sparse_component_costs(p, so), InputError);
  EXPECT_THROW(solve_sparse_association(p, "lr", nlohmann::json::object(), 1, so), InputError);
}
}  // namespace
}  // namespace trackassoc
