// --schedule, --restarts, --polish and --trace: the Hopfield solvers' flags (`associate`, `run`,
// `solve3d`), checked against the solver registry's capability flags and merged into --options.
#pragma once

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/cli/common.hpp"
#include "engine/solvers/hopfield_json.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::cli {

// --schedule, --restarts, --polish and --trace for the Hopfield solvers (hopfield_solver_names()),
// merged into their solver options (engine/solvers/hopfield_json.hpp); solve3d, associate and run.
struct HopfieldFlags {
  std::string schedule;
  int restarts = 0;
  bool polish = false, trace = false;
  bool any() const { return !schedule.empty() || restarts > 0 || polish || trace; }
};

// Whether `name` takes the Hopfield options (a 3-D registry entry that lists schedules).
inline bool is_hopfield_solver(const std::string& name) {
  const SolverEntry* e = lookup_solver(name);
  return e && e->capabilities.tensor3 && !e->capabilities.schedules.empty();
}

inline void add_hopfield_flags(CLI::App* cmd, HopfieldFlags& f, bool with_trace) {
  std::string schedules;  // each Hopfield solver's own, from the registry's capability flags
  for (const std::string& n : hopfield_solver_names())
    schedules +=
        (schedules.empty() ? "" : "; ") + n + ": " + list_names(find_solver(n).capabilities.schedules, ", ");
  cmd->add_option("--schedule", f.schedule,
                  "Hopfield solvers: the discrete network's sweeps (sync, async, diagonal) or the continuous "
                  "network's Euler steps (sync, async; continuous = sync). Per solver: " +
                      schedules);
  cmd->add_option("--restarts", f.restarts, "Hopfield solvers: number of restarts")
      ->check(in_range(1, std::numeric_limits<int32_t>::max()));
  cmd->add_flag("--polish", f.polish, "Hopfield solvers: polish every restart by the LAP local search");
  if (with_trace)
    cmd->add_flag(
        "--trace", f.trace,
        "Hopfield solvers: record the energy after every sweep of every restart (/associations/NAME/energy)");
}

// Why Hopfield solver `solver` cannot run `schedule` (the text of its options' error), or "" if
// the registry lists the schedule among the solver's capabilities.
inline std::string hopfield_schedule_rejection(const std::string& solver, const std::string& schedule) {
  const auto& own = find_solver(solver).capabilities.schedules;
  if (std::find(own.begin(), own.end(), schedule) != own.end()) return "";
  return hopfield_preset_schedule_error(solver, schedule);
}

// Merges the flags into `options` of solver `solver`; an InputError when a flag is given for a
// solver that is not a Hopfield network.
inline void merge_hopfield_flags(const HopfieldFlags& f, const std::string& solver, nlohmann::json& options) {
  if (!f.any()) return;
  if (!is_hopfield_solver(solver))
    throw InputError("--schedule/--restarts/--polish/--trace: only for " +
                     list_names(hopfield_solver_names()) + ", not '" + solver + "'");
  if (options.is_null()) options = nlohmann::json::object();
  if (!f.schedule.empty()) options["schedule"] = f.schedule;
  if (f.restarts > 0) options["restarts"] = f.restarts;
  if (f.polish) options["polish"] = true;
  if (f.trace) options["trace"] = true;
}

}  // namespace trackassoc::cli
