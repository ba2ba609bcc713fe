// The Hopfield solvers of the registry ("hopfield", "hopfield-paper", "chnn"): presets and the
// JSON options they accept (engine/solvers/solver_registry.hpp). Unknown keys and bad values are
// InputErrors naming the key.
//
// Keys (all optional): energy ("full_plane" | "printed"), schedule (hopfield, hopfield-paper: "sync" |
// "async" | "diagonal"; chnn: "sync" | "async" Euler steps, "continuous" = "sync"), restarts, max_sweeps,
// init ("zero" | "random" | "greedy" | "mean_field"), init_density, greedy_noise, order ("random" |
// "slice_random" | "cost"), anneal_E_factor, anneal_sweeps, temperature, damping, continuous_async, dt, tau,
// u0_start, u0_end, noise, tolerance, mean_field_steps, gain_anneal_steps, self_excitation, repair ("greedy"
// | "lap"), trace (bool), polish (bool: LAP local search on every restart), and A, B, C, D, E (giving any of
// them switches off the automatic weights; the others keep the preset's values).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/solvers/option_fields.hpp"
#include "kernels/assignment/assignment_types.hpp"
#include "kernels/hopfield/hopfield.hpp"

namespace trackassoc {

// The preset of a registry name: "hopfield" (the measured defaults), "hopfield-paper" (seed 000
// as printed: Eq. 11, A=B=C=300, D=200, E=1100, async from the empty state, one run) or "chnn"
// (continuous network, seed 004). Throws InputError for another name.
HopfieldOptions hopfield_preset(const std::string& name);
// The preset names, in registry order ("hopfield", "hopfield-paper", "chnn"), and their
// one-line descriptions (InputError for another name).
const std::vector<std::string>& hopfield_preset_names();
std::string hopfield_preset_description(const std::string& name);

// The values of the "schedule" key a network takes: discrete "sync" | "async" | "diagonal";
// continuous "sync" | "async" | "continuous" (= "sync").
std::vector<std::string> hopfield_schedule_names(HopfieldNetwork network);
// Why `network` cannot run `schedule` (the text of the options' InputError after "solver 'NAME'
// options: "), or "" when it can.
std::string hopfield_schedule_error(HopfieldNetwork network, const std::string& schedule);
// Why the preset `name` cannot run `schedule` (its network's schedules, then
// HopfieldOptions::validate: diagonal needs the full-plane energy and D = 0), as the full message of
// hopfield_options_from_json(name, {"schedule": schedule}); "" when it can.
std::string hopfield_preset_schedule_error(const std::string& name, const std::string& schedule);
// The schedules the preset `name` runs (the registry's capabilities.schedules).
std::vector<std::string> hopfield_preset_schedules(const std::string& name);

// The options declared once (engine/solvers/option_fields.hpp), in the order of the keys above; their
// help() lists key, default, range and doc.
const OptionFields<HopfieldOptions>& hopfield_option_fields();

// The preset overridden by `options`; `polish` mirrors the "polish" key.
HopfieldOptions hopfield_options_from_json(const std::string& name, const nlohmann::json& options,
                                           bool& polish);

// The fields of `options` as JSON (A..E only when the weights are not automatic): read back by
// hopfield_options_from_json with the same preset, it gives `options` again.
nlohmann::json hopfield_options_to_json(const HopfieldOptions& options);

// Runs the solver: Solution3 with the energy trace (restarts × sweeps) when "trace" is set; the
// summary message carries the raw validity rate.
Solution3 solve_hopfield_json(const std::string& name, const CostTensor3& cost, const nlohmann::json& options,
                              uint64_t seed);

}  // namespace trackassoc
