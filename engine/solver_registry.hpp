// The 3-D assignment solvers by name, so that the pipeline, `associate`, `run` and `solve3d`
// can swap them (Stone Soup: one narrow interface per stage).
//
// A solver entry turns (cost tensor, options as JSON, seed) into a Solution3. Each solver parses
// its JSON into its own XxxOptions, whose validate() names the bad field; unknown keys are an
// InputError. The same JSON is recorded in /associations/<name>/ attrs "options".
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/option_fields.hpp"
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

// in_limits and read_option_number: engine/option_fields.hpp (options declared once).

// Helper for solver adapters: throws InputError if `options` has a key not in `known`.
void reject_unknown_keys(const nlohmann::json& options, const std::vector<std::string>& known,
                         const std::string& solver);

// "unknown key 'restart' (did you mean 'restarts'?); known keys: a, b" for a solver's `key` not
// in `known`; "did you mean" names the known key at the smallest edit distance when it is <= 2 (or
// a third of the key's length). `kind` is "key" or "solver".
std::string unknown_name_message(const std::string& kind, const std::string& name,
                                 const std::vector<std::string>& known);

}  // namespace trackassoc
