#include "engine/solvers/solver_registry.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/solvers/chnn_pseudo_solver.hpp"
#include "engine/solvers/hopfield_json.hpp"
#include "engine/solvers/relaxation_solvers.hpp"
#include "kernels/assignment/assignment_canonical.hpp"
#include "kernels/assignment/heuristic_solvers.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

// A 3-D solver with dummies and no other capability (the baselines).
SolverEntry baseline_entry(std::string name, std::string description,
                           std::function<Solution3(const CostTensor3&)> solve) {
  SolverEntry e = solver_entry(name, std::move(description));
  e.solve = [name, solve](const CostTensor3& b, const nlohmann::json& o, uint64_t) {
    reject_unknown_keys(o, {}, name);
    return solve(b);
  };
  e.capabilities.tensor3 = e.capabilities.dummies = true;
  e.options_help = [] { return std::string("  (no options)\n"); };
  return e;
}

// The Hopfield network `name` (kernels/hopfield/hopfield.hpp; presets and options:
// engine/solvers/hopfield_json.hpp).
SolverEntry hopfield_entry(const std::string& n) {
  SolverEntry e = solver_entry(n, hopfield_preset_description(n), 200);
  e.solve = [n](const CostTensor3& b, const nlohmann::json& o, uint64_t seed) {
    if (!std::isfinite(b.miss_cost)) return solve_hopfield_json(n, b, o, seed);
    // Dummy index (finite miss_cost): the networks need complete tuples, so they
    // solve the padded cube of assignment_canonical.hpp, which is exact.
    const CanonicalProblem3 cube = make_canonical(b);
    Solution3 s = solve_hopfield_json(n, cube.tensor, o, seed);
    s.tuples = to_original(cube, s.tuples);
    finish_summary(b, s.tuples, std::numeric_limits<double>::quiet_NaN(), s.summary);
    s.summary.message += "; dummy indices padded to n1+n2+n3";
    return s;
  };
  e.capabilities.tensor3 = e.capabilities.dummies = true;
  e.capabilities.schedules = hopfield_preset_schedules(n);
  e.capabilities.restarts = true;
  e.options_help = [n] { return hopfield_option_fields().help(hopfield_preset(n)); };
  return e;
}

// seed 004's CHNN with pseudo-tracks: S-D only, on the whole problem (it needs the distances λ).
SolverEntry chnn_pseudo_entry() {
  SolverEntry e =
      solver_entry("chnn-pseudo", "continuous Hopfield network with pseudo-tracks (seed 004), S-D only");
  e.capabilities.sd = true;
  e.solve_sd = [](const SDProblemView& p, const nlohmann::json& o, uint64_t seed) {
    return solve_chnn_sd(p, o, seed);
  };
  e.options_help = [] { return chnn_pseudo_option_fields().help(ChnnPseudoSolverOptions{}); };
  return e;
}

// Each flag with its solve function (a registry bug, not an input error).
void check_entry(const SolverEntry& e) {
  const SolverCapabilities& c = e.capabilities;
  if (c.tensor3 != static_cast<bool>(e.solve) || c.sd_tensor != static_cast<bool>(e.solve_sd_tensor) ||
      c.sd != (c.sd_tensor || static_cast<bool>(e.solve_sd)) || (c.dummies && !c.tensor3))
    throw std::logic_error("solver registry: the capabilities of '" + e.name +
                           "' do not match its solve functions");
  if (!e.options_help) throw std::logic_error("solver registry: '" + e.name + "' documents no options");
}

std::vector<SolverEntry> make_registry() {
  std::vector<SolverEntry> r;
  r.push_back(baseline_entry("greedy", "cheapest free tuple first (baseline)",
                             [](const CostTensor3& b) { return solve_greedy3(b, GreedyOptions{}); }));
  r.push_back(baseline_entry("pairwise", "sequential pairwise LAP: 1-2, then the pairs against 3",
                             [](const CostTensor3& b) { return solve_pairwise3(b, PairwiseOptions{}); }));
  register_relaxation_solvers(r);  // lr, lr+ls, exact
  for (const std::string& n : hopfield_preset_names()) r.push_back(hopfield_entry(n));
  // Further 3-D solvers register here.
  register_local_search_variants(r);  // "X+ls" for every 3-D solver above: keep this after them
  r.push_back(chnn_pseudo_entry());   // S-D only
  for (const auto& e : r) check_entry(e);
  return r;
}

}  // namespace

const std::vector<SolverEntry>& all_solvers() {
  static const std::vector<SolverEntry> registry = make_registry();
  return registry;
}

const SolverEntry* lookup_solver(const std::string& name) {
  for (const auto& e : all_solvers())
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> solver_names_with(bool SolverCapabilities::*flag) {
  std::vector<std::string> names;
  for (const auto& e : all_solvers())
    if (e.capabilities.*flag) names.push_back(e.name);
  return names;
}

void require_solver_among(const std::string& name, const std::vector<std::string>& names,
                          const std::string& refusal, const std::string& tail) {
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string known;
  for (const auto& n : names) known += " " + n;
  throw InputError("--solver: '" + name + "' " + refusal + ":" + known + tail);
}

std::string list_names(const std::vector<std::string>& names, const std::string& last) {
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i)
    list += (i == 0 ? "" : i + 1 == names.size() ? last : ", ") + names[i];
  return list;
}

const std::vector<SolverEntry>& solver_registry() {
  static const std::vector<SolverEntry> registry = [] {
    std::vector<SolverEntry> r;
    for (const auto& e : all_solvers())
      if (e.capabilities.tensor3) r.push_back(e);
    return r;
  }();
  return registry;
}

const SolverEntry& find_solver(const std::string& name) {
  for (const auto& e : solver_registry())
    if (e.name == name) return e;
  std::vector<std::string> names;
  for (const auto& e : solver_registry()) names.push_back(e.name);
  throw InputError("--solver: " + unknown_name_message("solver", name, names));
}

std::vector<std::string> hopfield_solver_names() {
  std::vector<std::string> names;
  for (const auto& e : solver_registry())
    if (!e.capabilities.schedules.empty()) names.push_back(e.name);
  return names;
}

namespace {

// Levenshtein distance (insertions, deletions, substitutions of one character).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string unknown_name_message(const std::string& kind, const std::string& name,
                                 const std::vector<std::string>& known) {
  std::string message = "unknown " + kind + " '" + name + "'";
  std::size_t best = std::string::npos;
  std::string closest;
  for (const auto& k : known) {
    const std::size_t d = edit_distance(name, k);
    if (d < best) best = d, closest = k;
  }
  if (!closest.empty() && best <= std::max<std::size_t>(2, name.size() / 3))
    message += " (did you mean '" + closest + "'?)";
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  return message + "; known " + kind + (known.size() == 1 ? "" : "s") + ": " + (list.empty() ? "none" : list);
}

void reject_unknown_keys(const nlohmann::json& options, const std::vector<std::string>& known,
                         const std::string& solver) {
  if (options.is_null()) return;
  if (!options.is_object()) throw InputError("solver '" + solver + "' options: expected a JSON object");
  for (auto it = options.begin(); it != options.end(); ++it)
    if (std::find(known.begin(), known.end(), it.key()) == known.end())
      throw InputError("solver '" + solver + "' options: " + unknown_name_message("key", it.key(), known));
}

}  // namespace trackassoc
