// The solver registry's capability flags are true to behaviour (issue 16 item 2): for every entry,
// the time limit, the schedules and the restarts it is flagged for are accepted and no others, a
// lower bound is reported iff flagged, and the S-D entries solve a small S-D instance (exact and
// lr+ls to the brute-force optimum). The name queries that the pipelines and the CLI use return
// the lists they had before the registry was merged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/random.hpp"
#include "tests/support/solver_test_support.hpp"

namespace trackassoc {
namespace {

using namespace testing_support;
using nlohmann::json;

CostTensor3 cube3(uint64_t seed) {
  CostTensor3 b(3, 3, 3);
  CounterRng rng(seed, 21, 0);
  for (float& v : b.cost) v = static_cast<float>(rng.uniform(0.0, 10.0));
  return b;
}

// S = 3 with dummies, sizes 2, 3, 2; every tuple finite.
CostTensorSD small_sd(uint64_t seed) {
  CostTensorSD c({2, 3, 2}, 0.f);
  CounterRng rng(seed, 22, 0);
  for (float& v : c.cost) v = static_cast<float>(rng.uniform(-6.0, 4.0));
  return c;
}

bool accepts3(const SolverEntry& e, const CostTensor3& b, const json& options) {
  try {
    e.solve(b, options, 1);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

bool accepts_sd(const SolverEntry& e, const CostTensorSD& c, const json& options) {
  try {
    e.solve_sd_tensor(c, options);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

bool listed(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(SolverRegistry, ThreeDimensionalFlagsMatchBehaviour) {
  const CostTensor3 b = cube3(1);
  const std::vector<std::string> candidates{"sync", "async", "diagonal", "continuous", "zigzag"};
  int checked = 0;
  for (const SolverEntry& e : all_solvers()) {
    if (!e.capabilities.tensor3) continue;
    SCOPED_TRACE(e.name);
    const SolverCapabilities& c = e.capabilities;
    EXPECT_EQ(accepts3(e, b, json{{"time_limit_s", 30.0}}), c.time_limit);
    EXPECT_EQ(accepts3(e, b, json{{"restarts", 2}}), c.restarts);
    for (const std::string& s : candidates) {
      SCOPED_TRACE("schedule " + s);
      EXPECT_EQ(accepts3(e, b, json{{"schedule", s}}), listed(c.schedules, s));
    }
    const Solution3 s = e.solve(b, json::object(), 1);
    expect_consistent(b, s);
    EXPECT_EQ(!std::isnan(s.summary.lower_bound), c.lower_bound);
    if (c.lower_bound) {
      EXPECT_LE(s.summary.lower_bound, brute_force_optimum(b) + 1e-4);
    }
    if (c.dummies) {
      CostTensor3 d = b;
      d.miss_cost = 2.0f;
      expect_consistent(d, e.solve(d, json::object(), 1));
    }
    ++checked;
  }
  EXPECT_EQ(checked, 13);
}

TEST(SolverRegistry, SDFlagsMatchBehaviour) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const CostTensorSD c = small_sd(seed);
    const double optimum = brute_force_sd(c);
    ASSERT_TRUE(std::isfinite(optimum));
    for (const SolverEntry& e : all_solvers()) {
      if (!e.capabilities.sd_tensor) continue;
      SCOPED_TRACE(e.name + " seed " + std::to_string(seed));
      EXPECT_EQ(accepts_sd(e, c, json{{"time_limit_s", 30.0}}), e.capabilities.time_limit);
      EXPECT_EQ(accepts_sd(e, c, json{{"restarts", 2}}), e.capabilities.restarts);
      EXPECT_EQ(accepts_sd(e, c, json{{"schedule", "sync"}}), !e.capabilities.schedules.empty());
      const SolutionSD s = e.solve_sd_tensor(c, json::object());
      EXPECT_TRUE(is_valid_assignment_sd(c, s.tuples));
      EXPECT_NEAR(s.summary.objective, assignment_cost_sd(c, s.tuples), 1e-4);
      EXPECT_GE(s.summary.objective, optimum - 1e-4);
      EXPECT_EQ(!std::isnan(s.summary.lower_bound), e.capabilities.lower_bound);
      if (e.capabilities.lower_bound) {
        EXPECT_LE(s.summary.lower_bound, optimum + 1e-4);
      }
      if (e.name == "exact" || e.name == "lr+ls") {
        EXPECT_NEAR(s.summary.objective, optimum, 1e-4);
      }
    }
  }
}

TEST(SolverRegistry, EveryFlagHasItsSolveFunction) {
  for (const SolverEntry& e : all_solvers()) {
    SCOPED_TRACE(e.name);
    EXPECT_EQ(static_cast<bool>(e.solve), e.capabilities.tensor3);
    EXPECT_EQ(static_cast<bool>(e.solve_sd_tensor), e.capabilities.sd_tensor);
    EXPECT_EQ(static_cast<bool>(e.solve_sd) || e.capabilities.sd_tensor, e.capabilities.sd);
    EXPECT_FALSE(e.description.empty());
  }
}

// The queries give the lists that were written out by hand before (solve3d --help, `run`, the
// S-D and sparse S-D pipelines' checks, the Hopfield flags).
TEST(SolverRegistry, NameQueriesKeepTheirLists) {
  std::vector<std::string> three_d;
  for (const SolverEntry& e : solver_registry()) three_d.push_back(e.name);
  EXPECT_EQ(three_d, (std::vector<std::string>{"greedy", "pairwise", "lr", "lr+ls", "exact", "hopfield",
                                               "hopfield-paper", "chnn", "greedy+ls", "pairwise+ls",
                                               "hopfield+ls", "hopfield-paper+ls", "chnn+ls"}));
  EXPECT_EQ(sd_solver_names(), (std::vector<std::string>{"lr", "lr+ls", "exact", "chnn-pseudo"}));
  EXPECT_EQ(sparse_sd_solver_names(), (std::vector<std::string>{"lr+ls", "lr", "exact"}));
  EXPECT_EQ(hopfield_solver_names(), (std::vector<std::string>{"hopfield", "hopfield-paper", "chnn"}));
  EXPECT_EQ(solver_names_with(&SolverCapabilities::time_limit),
            (std::vector<std::string>{"lr", "lr+ls", "exact"}));
  EXPECT_EQ(list_names(hopfield_solver_names()), "hopfield, hopfield-paper and chnn");
  EXPECT_EQ(list_names({"a"}), "a");
  EXPECT_EQ(find_solver("chnn").capabilities.schedules,
            (std::vector<std::string>{"sync", "async", "continuous"}));
  EXPECT_EQ(find_solver("hopfield").capabilities.schedules,
            (std::vector<std::string>{"sync", "async", "diagonal"}));
  // The printed energy of hopfield-paper has no diagonal schedule (it needs the full-plane energy).
  EXPECT_EQ(find_solver("hopfield-paper").capabilities.schedules,
            (std::vector<std::string>{"sync", "async"}));
  // chnn-pseudo is an S-D solver only: not a 3-D name, and require_sd_solver accepts it.
  EXPECT_THROW(find_solver("chnn-pseudo"), InputError);
  EXPECT_NO_THROW(require_sd_solver("chnn-pseudo"));
  EXPECT_THROW(require_sd_solver("hopfield"), InputError);
  EXPECT_THROW(require_sparse_sd_solver("chnn-pseudo"), InputError);
  EXPECT_EQ(lookup_solver("nonexistent"), nullptr);
}

// The S-D pipelines' checks of a solver name (the dense and the default pipeline's, and the
// tensor S-D solve's) share one helper, require_solver_among, and keep their messages, written out
// here as they were before it.
TEST(SolverRegistry, TheSDPipelinesRefuseOtherSolversWithTheirOwnMessages) {
  auto message = [](auto check, const std::string& name) {
    try {
      check(name);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(require_sd_solver, "hopfield"),
            "--solver: 'hopfield' is not an S-D solver; S-D solvers: lr lr+ls exact chnn-pseudo");
  EXPECT_EQ(
      message(require_sparse_sd_solver, "chnn-pseudo"),
      "--solver: 'chnn-pseudo' is not a solver of the default (sparse S-D) pipeline; its solvers: lr+ls "
      "lr exact (the 3-D solvers run with --solver NAME --3d)");
  EXPECT_EQ(message(require_sparse_sd_solver, "lr"), "accepted");
  EXPECT_EQ(message(
                [](const std::string& n) {
                  solve_sd_tensor(CostTensorSD({1, 1}), n, nlohmann::json::object());
                },
                "hopfield"),
            "--solver: 'hopfield' takes no cost tensor alone; tensor S-D solvers: lr lr+ls exact");
  EXPECT_EQ(message(
                [](const std::string& n) {
                  require_solver_among(n, {"a", "b"}, "is not a letter; letters");
                },
                "c"),
            "--solver: 'c' is not a letter; letters: a b");
}

// The options listing of every entry (`trackassoc solvers`) and its unknown-key error come from the
// same declaration: the keys the listing names are exactly the "known keys" of the error.
TEST(SolverRegistry, OptionsHelpNamesExactlyTheKeysTheSolverAccepts) {
  const CostTensor3 b = cube3(7);
  int checked = 0;
  for (const SolverEntry& e : all_solvers()) {
    SCOPED_TRACE(e.name);
    ASSERT_TRUE(e.options_help);
    std::vector<std::string> listed;
    std::istringstream lines(e.options_help());
    std::string line;
    bool header = true;
    while (std::getline(lines, line)) {
      std::istringstream words(line);
      std::string key;
      words >> key;
      if (header) {  // "key  default  range  doc", or "(no options)"
        header = false;
        if (key == "(no") break;
        EXPECT_EQ(key, "key");
        continue;
      }
      listed.push_back(key);
    }
    std::string message;
    try {
      if (e.capabilities.tensor3)
        e.solve(b, json{{"zz_not_a_key", 1}}, 1);
      else
        continue;  // chnn-pseudo needs a whole SDProblem: its fields are held by test_option_fields
    } catch (const InputError& err) {
      message = err.what();
    }
    ASSERT_NE(message.find("unknown key 'zz_not_a_key'"), std::string::npos) << message;
    const auto at = message.find(": ", message.find("; known key"));
    ASSERT_NE(at, std::string::npos) << message;
    std::vector<std::string> known;
    if (message.substr(at + 2) != "none") {
      std::istringstream rest(message.substr(at + 2));
      std::string k;
      while (std::getline(rest, k, ',')) known.push_back(k.substr(k.find_first_not_of(' ')));
    }
    std::sort(listed.begin(), listed.end());
    std::sort(known.begin(), known.end());
    EXPECT_EQ(listed, known) << e.options_help() << message;
    ++checked;
  }
  EXPECT_EQ(checked, 13);
}

}  // namespace
}  // namespace trackassoc
