// The 3-D assignment solvers by name, so that the pipeline, `associate`, `run` and `solve3d`
// can swap them (Stone Soup: one narrow interface per stage).
//
// A solver entry turns (cost tensor, options as JSON, seed) into a Solution3. Each solver parses
// its JSON into its own XxxOptions, whose validate() names the bad field; unknown keys are an
// InputError. The same JSON is recorded in /associations/<name>/ attrs "options".
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "kernels/assignment_types.hpp"
#include "kernels/error.hpp"

namespace trackassoc {

struct SolverEntry {
  std::string name;
  std::string description;
  // Solvers that scale badly (exact) are not run by `run` above this n = max(n1, n2, n3).
  int32_t max_default_n = 1 << 30;
  std::function<Solution3(const CostTensor3&, const nlohmann::json& options, uint64_t seed)> solve;
};

// All registered solvers, in the order `run` reports them.
const std::vector<SolverEntry>& solver_registry();
// Throws InputError listing the known names when `name` is unknown.
const SolverEntry& find_solver(const std::string& name);

// Reads an optional number; a wrong type is an InputError naming solver and key.
template <class T>
void read_option_number(const nlohmann::json& o, const char* key, T& target, const std::string& solver) {
  if (o.is_null() || !o.contains(key)) return;
  const auto& v = o.at(key);
  if (!v.is_number()) throw InputError("solver '" + solver + "' options: '" + key + "' must be a number");
  if constexpr (std::is_integral_v<T>) {
    if (!v.is_number_integer())
      throw InputError("solver '" + solver + "' options: '" + key + "' must be an integer");
  }
  target = v.get<T>();
}

// Helper for solver adapters: throws InputError if `options` has a key not in `known`.
void reject_unknown_keys(const nlohmann::json& options, const std::vector<std::string>& known,
                         const std::string& solver);

}  // namespace trackassoc
