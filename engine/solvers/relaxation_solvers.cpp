#include "engine/solvers/relaxation_solvers.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/branch_and_bound.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/assignment/local_search.hpp"
#include "kernels/assignment/sd/assignment_sd.hpp"
#include "kernels/assignment/sd/lagrangian_sd.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {
namespace {

// A finite miss cost: the S-D branch and bound on the same problem (assignment_sd.hpp's to_sd keeps
// the 3-D semantics), started from lr+ls. The 3-D search on the padded (n1+n2+n3)-cube is far
// slower (about 20 s for 3×4×3).
Solution3 solve_exact_with_dummies(const CostTensor3& b, const BranchAndBoundOptions& bo) {
  const auto t0 = std::chrono::steady_clock::now();
  const CostTensorSD c = to_sd(b, b.miss_cost);
  LagrangianOptions lo;
  lo.local_search = true;
  const SolutionSD start = solve_lagrangian_sd(c, lo);
  ExactSDOptions eo;
  eo.time_limit_s = bo.time_limit_s;
  eo.max_nodes = bo.max_nodes;
  const SolutionSD sd =
      start.summary.termination == Termination::kOptimal ? start : solve_exact_sd(c, eo, &start.tuples);
  Solution3 s;
  for (std::size_t k = 0; k < sd.tuples.size(); k += 3)
    s.tuples.push_back({sd.tuples[k], sd.tuples[k + 1], sd.tuples[k + 2]});
  s.summary.termination = sd.summary.termination;
  s.summary.iterations = sd.summary.iterations;
  finish_summary(b, s.tuples, sd.summary.lower_bound, s.summary);
  s.summary.message = "dummy indices: S-D branch and bound (" + sd.summary.message + ")";
  s.summary.wall_time_s = seconds_since(t0);
  return s;
}

}  // namespace

const OptionFields<LagrangianOptions>& lagrangian_option_fields(bool with_ls) {
  using O = LagrangianOptions;
  auto make = [](bool ls) {
    std::vector<OptionField<O>> f{
        field("max_iterations", &O::max_iterations, ">= 1", "subgradient iterations"),
        field("relative_gap_tolerance", &O::relative_gap_tolerance, ">= 0",
              "stop when (UB − LB) / max(|UB|, 1e-9) <= this"),
        field("absolute_gap_tolerance", &O::absolute_gap_tolerance, ">= 0",
              "stop (optimal) when UB − LB <= this"),
        field("time_limit_s", &O::time_limit_s, "> 0", "wall-time limit [s] (default: none)"),
        field("step_rule", &O::step_rule, "", "subgradient step rule"),
        field("theta", &O::theta, "(0, 2]", "initial step scale θ"),
        field("theta_patience", &O::theta_patience, ">= 1",
              "halve θ after this many iterations without a better bound"),
        field("min_theta", &O::min_theta, "(0, theta]", "stop when θ falls below this")};
    if (ls)
      f.push_back(field("max_rounds", path(&O::local_search_options, &LocalSearchOptions::max_rounds), ">= 1",
                        "local search rounds per recovered solution (a round tries all three moves)"));
    return OptionFields<O>(std::move(f));
  };
  static const OptionFields<O> lr = make(false), lr_ls = make(true);
  return with_ls ? lr_ls : lr;
}

LagrangianOptions lagrangian_options(const nlohmann::json& o, const std::string& solver, bool with_ls) {
  LagrangianOptions lo;
  lagrangian_option_fields(with_ls).read(o, lo, solver);
  lo.local_search = with_ls;
  lo.validate();
  return lo;
}

const OptionFields<BranchAndBoundOptions>& exact_option_fields() {
  using O = BranchAndBoundOptions;
  static const OptionFields<O> fields{{
      field("time_limit_s", &O::time_limit_s, "> 0",
            "wall-time limit [s]; then the best tuples and the bound"),
      field("max_nodes", &O::max_nodes, ">= 1", "search-tree nodes at most"),
      field("node_subgradient_iterations", &O::node_subgradient_iterations, ">= 1",
            "subgradient steps per node to sharpen its bound"),
      field("reduced_cost_fixing", &O::reduced_cost_fixing, "",
            "fix tuples to 0 by their root reduced cost in every search pass"),
      field("root_max_iterations", path(&O::root, &LagrangianOptions::max_iterations), ">= 1",
            "subgradient iterations of the root relaxation"),
  }};
  return fields;
}

const OptionFields<ExactSDOptions>& exact_sd_option_fields() {
  using O = ExactSDOptions;
  static const OptionFields<O> fields{{
      field("time_limit_s", &O::time_limit_s, "> 0",
            "wall-time limit [s]; then the best tuples and the bound"),
      field("max_nodes", &O::max_nodes, ">= 1", "search-tree nodes at most"),
  }};
  return fields;
}

ExactSDOptions exact_sd_options(const nlohmann::json& o, const std::string& solver) {
  ExactSDOptions eo;
  exact_sd_option_fields().read(o, eo, solver);
  eo.validate();
  return eo;
}

const OptionFields<PolishOptions>& polish_option_fields() {
  using O = PolishOptions;
  static const OptionFields<O> fields{{
      field("max_rounds", path(&O::local_search, &LocalSearchOptions::max_rounds), ">= 1",
            "local search rounds (a round tries all three moves)"),
      {"base", "{...}", "the options of the base solver",
       [](O& o, const nlohmann::json& v, const std::string&, const std::string&) { o.base = v; },
       [](const O& o) -> std::optional<nlohmann::json> {
         if (o.base.is_null()) return std::nullopt;
         return o.base;
       }},
  }};
  return fields;
}

namespace {

// The S-D exact solver on a tensor: the S-D branch and bound started from lr+ls, whose bound may
// already prove it optimal.
SolutionSD solve_exact_sd_tensor(const CostTensorSD& tensor, const nlohmann::json& options) {
  const ExactSDOptions eo = exact_sd_options(options, "exact");
  LagrangianOptions lo;
  lo.local_search = true;
  const SolutionSD start = solve_lagrangian_sd(tensor, lo);
  if (start.summary.termination == Termination::kOptimal) {
    SolutionSD sol = start;  // the relaxation's bound already proves lr+ls optimal
    sol.summary.message = "proven optimal by the S-D relaxation's bound (no search needed)";
    return sol;
  }
  SolutionSD sol = solve_exact_sd(tensor, eo, &start.tuples);
  if (sol.summary.termination == Termination::kTimeLimit &&
      start.summary.lower_bound > sol.summary.lower_bound)
    set_bound_and_gap(sol.summary, start.summary.lower_bound);
  return sol;
}

// lr, lr+ls and exact: 3-D (with dummies) and S-D on a tensor, with a time limit and a lower bound.
SolverCapabilities relaxation_capabilities() {
  SolverCapabilities c;
  c.tensor3 = c.dummies = c.sd = c.sd_tensor = c.time_limit = c.lower_bound = true;
  return c;
}

SolverEntry lagrangian_entry(const std::string& name, const std::string& description, bool with_ls) {
  SolverEntry e = solver_entry(name, description);
  e.solve = [name, with_ls](const CostTensor3& b, const nlohmann::json& o, uint64_t) {
    return solve_lagrangian3(b, lagrangian_options(o, name, with_ls));
  };
  e.capabilities = relaxation_capabilities();
  e.solve_sd_tensor = [name, with_ls](const CostTensorSD& c, const nlohmann::json& o) {
    return solve_lagrangian_sd(c, lagrangian_options(o, name, with_ls));
  };
  e.options_help = [name, with_ls] {
    return lagrangian_option_fields(with_ls).help(lagrangian_options(nlohmann::json(), name, with_ls));
  };
  return e;
}

}  // namespace

void register_relaxation_solvers(std::vector<SolverEntry>& r) {
  r.push_back(lagrangian_entry(
      "lr", "Lagrangian relaxation (subgradient, LAP recovery) with lower bound and gap", false));
  r.push_back(lagrangian_entry(
      "lr+ls", "Lagrangian relaxation, each recovered solution polished by local search", true));
  SolverEntry exact =
      solver_entry("exact", "branch and bound with Lagrangian bounds (proven optimum or time limit)", 30);
  exact.solve = [](const CostTensor3& b, const nlohmann::json& o, uint64_t) {
    BranchAndBoundOptions bo;
    exact_option_fields().read(o, bo, "exact");
    bo.validate();
    if (std::isfinite(b.miss_cost)) return solve_exact_with_dummies(b, bo);
    return solve_branch_and_bound3(b, bo);
  };
  exact.capabilities = relaxation_capabilities();
  exact.solve_sd_tensor = solve_exact_sd_tensor;
  exact.options_help = [] { return exact_option_fields().help(BranchAndBoundOptions{}); };
  r.push_back(std::move(exact));
}

void register_local_search_variants(std::vector<SolverEntry>& r) {
  const std::size_t n = r.size();
  for (std::size_t e = 0; e < n; ++e) {
    const SolverEntry base = r[e];
    const std::string name = base.name + "+ls";
    if (!base.capabilities.tensor3 || base.name == "exact" || base.name.ends_with("+ls")) continue;
    bool exists = false;
    for (const auto& x : r) exists |= x.name == name;
    if (exists) continue;
    SolverEntry v = solver_entry(name, base.description + ", polished by local search", base.max_default_n);
    v.solve = [base, name](const CostTensor3& b, const nlohmann::json& o, uint64_t seed) {
      PolishOptions po;
      polish_option_fields().read(o, po, name);
      po.local_search.validate();
      const auto t0 = std::chrono::steady_clock::now();
      const Solution3 start = base.solve(b, po.base, seed);
      Solution3 s = solve_local_search3(b, start.tuples, po.local_search);
      // Keep the base's bound (still valid) and recompute the gap for the polished result.
      if (!std::isnan(start.summary.lower_bound)) set_bound_and_gap(s.summary, start.summary.lower_bound);
      s.summary.iterations = start.summary.iterations;
      s.summary.message =
          "polished " + base.name + " (objective " + std::to_string(start.summary.objective) + ")";
      s.summary.wall_time_s = seconds_since(t0);
      return s;
    };
    // 3-D only, its own options (max_rounds, base): the base's bound is kept.
    v.capabilities.tensor3 = true;
    v.capabilities.dummies = base.capabilities.dummies;
    v.capabilities.lower_bound = base.capabilities.lower_bound;
    v.options_help = [] { return polish_option_fields().help(PolishOptions{}); };
    r.push_back(std::move(v));
  }
}

}  // namespace trackassoc
