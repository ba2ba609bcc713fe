// Every assignment solver by name, with what it can do, so that the pipelines, `associate`,
// `run` and `solve3d` can swap them and their help and validation read the flags (Stone Soup: one
// narrow interface per stage).
//
// An entry turns (cost tensor, options as JSON, seed) into a solution: a 3-D CostTensor3 into a
// Solution3 (`solve`), and/or the S-D formulation with a dummy per sensor into a SolutionSD
// (`solve_sd_tensor` on the cost tensor alone, `solve_sd` on the whole problem, SDProblemView). A 3-D solver
// and an S-D solver of the same name (lr, lr+ls, exact) are one entry with both. Each solver
// parses its JSON into its own XxxOptions, whose validate() names the bad field; unknown keys are
// an InputError. The same JSON is recorded in /associations/<name>/ attrs "options".
//
// Adding a solver: one entry in make_registry() (engine/solvers/solver_registry.cpp) or in the
// register_* function of its family, with its flags; tests/engine/solvers/test_solver_registry.cpp holds
// every flag to the behaviour.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/solvers/option_fields.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

// What a whole-problem S-D solver (`solve_sd`: chnn-pseudo) sees of the S-D problem that
// engine/pipeline/pipeline_sd.hpp builds (sd_problem_view there), in tensor order.
struct SDProblemView {
  std::vector<int32_t> tracks;           // local tracks per sensor
  std::span<const PairStatistic> pairs;  // pairs[a·S + b] for a < b
  std::span<const double> gate;          // γ at the pair's largest dof, per pair slot
  const CostTensorSD* tensor = nullptr;  // the S-D cost tensor the tuples are scored on
  int32_t S() const { return static_cast<int32_t>(tracks.size()); }
};

struct SolverCapabilities {
  bool tensor3 = false;     // solves the 3-D cost tensor (`solve`)
  bool dummies = false;     // tensor3 with a finite miss_cost (the dummy index of every dimension)
  bool sd = false;          // solves the S-D formulation with dummies (`solve_sd_tensor` or `solve_sd`)
  bool sd_tensor = false;   // ... on its cost tensor alone (`solve_sd_tensor`): the sparse S-D components
  bool time_limit = false;  // takes the option "time_limit_s" (solve3d --time-limit)
  std::vector<std::string> schedules;  // the values of the option "schedule" it takes (Hopfield)
  bool restarts = false;               // takes the option "restarts" (Hopfield)
  bool lower_bound = false;            // reports a lower bound (summary.lower_bound not NaN)
};

struct SolverEntry {
  std::string name;
  std::string description;
  // Solvers that scale badly (exact) are not run by `run` above this n = max(n1, n2, n3).
  int32_t max_default_n = 1 << 30;
  std::function<Solution3(const CostTensor3&, const nlohmann::json& options, uint64_t seed)> solve;
  SolverCapabilities capabilities;
  std::function<SolutionSD(const CostTensorSD&, const nlohmann::json& options)> solve_sd_tensor;
  std::function<SolutionSD(const SDProblemView&, const nlohmann::json& options, uint64_t seed)> solve_sd;
  // Its options, one line per field (key, default, range, doc), from the fields' one declaration
  // (engine/solvers/option_fields.hpp): `trackassoc solvers` prints it.
  std::function<std::string()> options_help;
};

// An entry with a name, a description and no solve function or flag yet.
inline SolverEntry solver_entry(std::string name, std::string description, int32_t max_default_n = 1 << 30) {
  SolverEntry e;
  e.name = std::move(name);
  e.description = std::move(description);
  e.max_default_n = max_default_n;
  return e;
}

// Every registered solver: the 3-D solvers in the order `run` reports them, then the S-D-only ones.
const std::vector<SolverEntry>& all_solvers();
// The entry named `name`, or nullptr.
const SolverEntry* lookup_solver(const std::string& name);
// The names of the entries whose capability `flag` is set, in registry order.
std::vector<std::string> solver_names_with(bool SolverCapabilities::*flag);
// Returns when `name` is one of `names`; else throws InputError
// "--solver: '<name>' <refusal>:" + " <n>" per name + `tail` (the S-D pipelines' checks:
// require_sd_solver, require_sparse_sd_solver, solve_sd_tensor).
void require_solver_among(const std::string& name, const std::vector<std::string>& names,
                          const std::string& refusal, const std::string& tail = "");
// "a, b and c" (`last` between the last two; ", " between the others).
std::string list_names(const std::vector<std::string>& names, const std::string& last = " and ");

// The 3-D solvers (capabilities.tensor3), in the order `run` reports them.
const std::vector<SolverEntry>& solver_registry();
// The 3-D solver `name`; throws InputError listing the known names when there is none.
const SolverEntry& find_solver(const std::string& name);
// The 3-D solvers that take the Hopfield options schedule, restarts, polish and trace (and the
// --schedule/--restarts/--polish/--trace flags): "hopfield", "hopfield-paper", "chnn".
std::vector<std::string> hopfield_solver_names();

// in_limits and read_option_number: engine/solvers/option_fields.hpp (options declared once).

// Helper for solver adapters: throws InputError if `options` has a key not in `known`.
void reject_unknown_keys(const nlohmann::json& options, const std::vector<std::string>& known,
                         const std::string& solver);

// "unknown key 'restart' (did you mean 'restarts'?); known keys: a, b" for a solver's `key` not
// in `known`; "did you mean" names the known key at the smallest edit distance when it is <= 2 (or
// a third of the key's length). `kind` is "key" or "solver".
std::string unknown_name_message(const std::string& kind, const std::string& name,
                                 const std::vector<std::string>& known);

}  // namespace trackassoc
