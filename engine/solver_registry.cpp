#include "engine/solver_registry.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "engine/hopfield_json.hpp"
#include "engine/relaxation_solvers.hpp"
#include "kernels/assignment_canonical.hpp"
#include "kernels/error.hpp"
#include "kernels/heuristic_solvers.hpp"

namespace trackassoc {
namespace {

std::vector<SolverEntry> make_registry() {
  std::vector<SolverEntry> r;
  r.push_back({"greedy", "cheapest free tuple first (baseline)", 1 << 30,
               [](const CostTensor3& b, const nlohmann::json& o, uint64_t) {
                 reject_unknown_keys(o, {}, "greedy");
                 return solve_greedy3(b, GreedyOptions{});
               }});
  r.push_back({"pairwise", "sequential pairwise LAP: 1-2, then the pairs against 3", 1 << 30,
               [](const CostTensor3& b, const nlohmann::json& o, uint64_t) {
                 reject_unknown_keys(o, {}, "pairwise");
                 return solve_pairwise3(b, PairwiseOptions{});
               }});
  register_relaxation_solvers(r);  // lr, lr+ls, exact
  // Hopfield solvers (kernels/hopfield.hpp; options: engine/hopfield_json.hpp).
  for (const char* name : {"hopfield", "hopfield-paper", "chnn"}) {
    const std::string n = name;
    const std::string desc =
        n == "hopfield" ? "discrete 3-D Hopfield network, full-plane energy, mean-field start (seed 000)"
        : n == "hopfield-paper"
            ? "discrete 3-D Hopfield network as printed (seed 000 Eq. 11, A=B=C=300, D=200, E=1100)"
            : "continuous Hopfield network with gain annealing (CHNN, seed 004)";
    r.push_back({n, desc, 200, [n](const CostTensor3& b, const nlohmann::json& o, uint64_t seed) {
                   if (!std::isfinite(b.miss_cost)) return solve_hopfield_json(n, b, o, seed);
                   // Dummy index (finite miss_cost): the networks need complete tuples, so they
                   // solve the padded cube of assignment_canonical.hpp, which is exact.
                   const CanonicalProblem3 cube = make_canonical(b);
                   Solution3 s = solve_hopfield_json(n, cube.tensor, o, seed);
                   s.tuples = to_original(cube, s.tuples);
                   finish_summary(b, s.tuples, std::numeric_limits<double>::quiet_NaN(), s.summary);
                   s.summary.message += "; dummy indices padded to n1+n2+n3";
                   return s;
                 }});
  }
  // Further solvers register here.
  register_local_search_variants(r);  // "X+ls" for every solver above: keep this last
  return r;
}

}  // namespace

const std::vector<SolverEntry>& solver_registry() {
  static const std::vector<SolverEntry> registry = make_registry();
  return registry;
}

const SolverEntry& find_solver(const std::string& name) {
  for (const auto& e : solver_registry())
    if (e.name == name) return e;
  std::vector<std::string> names;
  for (const auto& e : solver_registry()) names.push_back(e.name);
  throw InputError("--solver: " + unknown_name_message("solver", name, names));
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
