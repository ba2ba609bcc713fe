// Registry adapters of the relaxation-based 3-D and S-D solvers
// (kernels/assignment/lagrangian_relaxation.hpp, local_search.hpp, branch_and_bound.hpp): JSON options →
// XxxOptions, validated, unknown keys rejected. Called from make_registry() in solver_registry.cpp.
//
//   lr       Lagrangian relaxation. Options: max_iterations, relative_gap_tolerance,
//            absolute_gap_tolerance, time_limit_s, step_rule ("polyak" | "diminishing" |
//            "deflected"), theta, theta_patience, min_theta.
//   lr+ls    the same, each recovered solution polished by local search; adds max_rounds.
//   exact    branch and bound. Options: time_limit_s, max_nodes, node_subgradient_iterations,
//            reduced_cost_fixing, root_max_iterations. Not run by `run` above n = 30 (max_default_n).
//   lr, lr+ls, exact also solve the S-D formulation (solve_sd_tensor):
//   kernels/assignment/sd/lagrangian_sd.hpp
//            with the same options; exact = kernels/assignment/sd/assignment_sd.hpp's branch and bound
//            (options time_limit_s, max_nodes) started from lr+ls.
//   X+ls     for every other registered solver X: X's result polished by local search. Options:
//            max_rounds, plus X's own options under the key "base".
#pragma once

#include <vector>

#include "engine/solvers/solver_registry.hpp"
#include "kernels/assignment/branch_and_bound.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"

namespace trackassoc {

// The option fields of each solver (engine/solvers/option_fields.hpp: read, write, help), in the order of
// the keys above.
const OptionFields<LagrangianOptions>& lagrangian_option_fields(bool with_ls);
const OptionFields<BranchAndBoundOptions>& exact_option_fields();
const OptionFields<ExactSDOptions>& exact_sd_option_fields();  // the S-D exact: time_limit_s, max_nodes
// X+ls: the local search's max_rounds, and the base solver's own options (passed on unread).
struct PolishOptions {
  LocalSearchOptions local_search;
  nlohmann::json base;
};
const OptionFields<PolishOptions>& polish_option_fields();

// JSON → LagrangianOptions for lr (and lr+ls when with_ls, adding max_rounds); validated. Shared
// with the S-D solvers (engine/pipeline/pipeline_sd.hpp).
LagrangianOptions lagrangian_options(const nlohmann::json& o, const std::string& solver, bool with_ls);
// JSON → ExactSDOptions of the S-D exact solver; validated.
ExactSDOptions exact_sd_options(const nlohmann::json& o, const std::string& solver);

// Appends lr, lr+ls and exact (3-D and S-D; time limit, lower bound).
void register_relaxation_solvers(std::vector<SolverEntry>& registry);
// Appends "X+ls" for every 3-D entry X already present that is not exact and has no "+ls" twin
// (3-D only; options max_rounds and base).
void register_local_search_variants(std::vector<SolverEntry>& registry);

}  // namespace trackassoc
