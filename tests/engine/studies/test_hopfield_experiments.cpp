// The Hopfield experiments of issue 5 (engine/studies/seed000/experiment_schedules.hpp,
// engine/studies/seed000/experiment_seed000.hpp): every row against numbers worked out independently (the
// known optima of ap3.opt, a fresh LR bound, a fresh library solve, the recomputed gap) and the HDF5 output
// read back. Seed 000's correlated errors and its decoded scoring: tests/test_seed000_study.cpp.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "engine/simulation/simulation.hpp"
#include "engine/studies/seed000/experiment_schedules.hpp"
#include "engine/studies/seed000/experiment_seed000.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/instance_text.hpp"
#include "kernels/assignment/heuristic_solvers.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/core/error.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "tests/support/io_test_files.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using test::TempDir;
using testing_support::decomplib;

SchedulesExperimentOptions small_schedules(const TempDir& dir) {
  SchedulesExperimentOptions o;
  o.tracking_sizes = {8};
  o.runs = 2;
  o.decomplib_sizes = {10};
  o.decomplib_per_size = 2;
  o.decomplib_dir = decomplib("");
  o.restarts = 2;
  o.methods = {"async/full", "diagonal/full", "greedy+ls", "lr"};
  o.seed = 5;
  o.output = dir.file("schedules.h5");
  o.plot = dir.file("schedules.svg");
  return o;
}

TEST(SchedulesExperiment, RowsAgreeWithIndependentSolvesAndTheFile) {
  const TempDir dir;
  const SchedulesExperimentOptions o = small_schedules(dir);
  const std::vector<ScheduleRow> rows = run_schedules_experiment(o, nullptr);
  ASSERT_EQ(rows.size(), 4u * 4u);  // (2 tracking + 2 DecompLib instances) × 4 methods
  const auto optima = read_known_optima(decomplib("ap3.opt"));
  for (const ScheduleRow& r : rows) {
    SCOPED_TRACE(r.instance + " / " + r.method);
    CostTensor3 cost;
    double reference = 0.0;
    if (r.family == "decomplib") {
      cost = read_3dap_instance(decomplib(r.instance + ".txt"));
      reference = optima.at(r.instance);  // the published optimum
    } else {
      ASSERT_EQ(r.family, "tracking");
      const int32_t run = r.instance.back() - '0';
      cost = seed000_tracking_instance(8, o.seed, run).cost;
      reference = solve_lagrangian3(cost, LagrangianOptions{}).summary.lower_bound;
    }
    EXPECT_EQ(r.reference, reference);
    EXPECT_TRUE(r.valid);
    EXPECT_GE(r.objective, reference - 1e-6 * std::abs(reference));  // a bound or the optimum
    EXPECT_NEAR(r.gap, (r.objective - reference) / std::abs(reference), 1e-12);
    // Every row's objective and work count from a fresh solve of the method: the networks' raw
    // validity is the share of restarts whose own state was an assignment and their sweeps the mean
    // over restarts of sweeps + mean-field steps, both counted here from the restarts; the local
    // search's rounds and LR's iterations are those of the fresh solve.
    const bool network = r.method == "async/full" || r.method == "diagonal/full";
    if (network) {
      HopfieldOptions h;  // async/full is the default hopfield, with the experiment's restarts and seed
      h.restarts = o.restarts;
      if (r.method == "diagonal/full") h.schedule = HopfieldSchedule::kDiagonal;
      const HopfieldResult fresh = solve_hopfield(cost, h, o.seed);
      ASSERT_EQ(fresh.restarts.size(), static_cast<std::size_t>(o.restarts));
      int raw_valid = 0;
      double sweeps = 0.0;
      for (const HopfieldRestart& rr : fresh.restarts) {
        raw_valid += rr.raw_feasible;
        sweeps += static_cast<double>(rr.sweeps + rr.mean_field_steps);
      }
      EXPECT_EQ(r.objective, fresh.solution.summary.objective);
      EXPECT_EQ(r.raw_validity, static_cast<double>(raw_valid) / o.restarts);
      EXPECT_EQ(r.sweeps, sweeps / o.restarts);
    } else {
      EXPECT_EQ(r.raw_validity, -1.0);
      if (r.method == "lr") {
        const Solution3 fresh = solve_lagrangian3(cost, LagrangianOptions{});
        EXPECT_EQ(r.objective, fresh.summary.objective);
        EXPECT_EQ(r.sweeps, static_cast<double>(fresh.summary.iterations));
      } else {
        ASSERT_EQ(r.method, "greedy+ls");
        const Solution3 fresh = solve_local_search3(cost, solve_greedy3(cost).tuples);
        EXPECT_EQ(r.objective, fresh.summary.objective);
        EXPECT_EQ(r.sweeps, static_cast<double>(fresh.summary.sweeps));
      }
    }
  }

  write_schedules_outputs(rows, o);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"schedules.h5", "schedules.svg"}));  // no .tmp left
  const h5::File f = h5::File::open_read_only(o.output);
  const h5::Group g = f.root().open_group("schedules");
  const auto methods =
      nlohmann::json::parse(g.read_string_attribute("methods")).get<std::vector<std::string>>();
  EXPECT_EQ(methods, o.methods);
  std::vector<hsize_t> dims;
  const std::vector<double> objective = g.read_doubles("objective", 1, dims),
                            gap = g.read_doubles("gap", 1, dims);
  const std::vector<int64_t> method = g.read_integers("method", 1, dims);
  ASSERT_EQ(objective.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(objective[i], rows[i].objective) << i;
    EXPECT_EQ(gap[i], rows[i].gap) << i;
    EXPECT_EQ(methods.at(static_cast<std::size_t>(method[i])), rows[i].method) << i;
  }
}

TEST(SchedulesExperiment, BadOptionsAreInputErrors) {
  const TempDir dir;
  SchedulesExperimentOptions o = small_schedules(dir);
  o.methods = {"async/full", "zigzag"};
  try {
    o.validate();
    ADD_FAILURE() << "no error for an unknown method";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("zigzag"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'async/full'"), std::string::npos) << e.what();  // the list
  }
  o = small_schedules(dir);
  o.decomplib_dir = dir.path();  // no ap3.opt there
  EXPECT_THROW(run_schedules_experiment(o, nullptr), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

// The Monte Carlo rows: one per (targets, errors, cost form, run, solver); exact is optimal, so no
// solver of the same run and form has a lower objective; every rate is a share; the summary names
// every solver.
TEST(Seed000Experiment, ExactIsNeverBeatenAndRatesAreShares) {
  const TempDir dir;
  Seed000ExperimentOptions o;
  o.targets = {6};
  o.runs = 3;
  o.solvers = {"hopfield", "lr", "exact"};
  o.output = dir.file("seed000.h5");
  o.plot = dir.file("seed000.svg");
  const std::vector<Seed000Row> rows = run_seed000_experiment(o, nullptr);
  ASSERT_EQ(rows.size(), 1u * 2u * 2u * 3u * 3u);
  std::map<std::tuple<bool, std::string, int32_t>, double> exact;
  for (const auto& r : rows)
    if (r.solver == "exact") exact[{r.correlated, r.form, r.run}] = r.objective;
  ASSERT_EQ(exact.size(), 12u);
  for (const auto& r : rows) {
    SCOPED_TRACE(r.solver + " " + r.form + " run " + std::to_string(r.run));
    EXPECT_GE(r.objective, exact.at({r.correlated, r.form, r.run}) - 1e-3 * (1.0 + std::abs(r.objective)));
  }
  const std::string table = seed000_summary_table(rows, o);
  for (const auto& s : o.solvers) EXPECT_NE(table.find(s), std::string::npos) << s;
  write_seed000_outputs(rows, o);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"seed000.h5", "seed000.svg"}));
}

}  // namespace
}  // namespace trackassoc
