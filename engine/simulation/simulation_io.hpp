// The simulation's input and output, shared by `simulate`, `run`, the studies, the benchmarks and
// the tests: where scenarios come from (a JSON file or an embedded scenario), and how a simulation
// becomes a schema v1 track file (docs/schema.md).
#pragma once

#include <string>

#include "engine/simulation/simulation.hpp"
#include "io/track_file.hpp"
#include "kernels/core/scenario.hpp"

namespace trackassoc {

// `name_or_path` is a JSON file path, or the name of an embedded scenario (data/scenarios/NAME.json,
// e.g. "seed000"). Throws InputError listing the embedded names when neither exists.
Scenario load_scenario(const std::string& name_or_path);

// A track file holding the scenario JSON, the sensors, the truth, the measurements and the tracks.
TrackFile simulation_to_track_file(const Scenario& scenario, const SimulationResult& result);
// As above, moving the tables (no second copy of a large simulation in memory).
TrackFile simulation_to_track_file(const Scenario& scenario, SimulationResult&& result);

}  // namespace trackassoc
