// Glue shared by the CLI commands and the experiments: where scenarios come from, and how a
// simulation becomes a schema v1 track file.
#pragma once

#include <string>

#include "engine/simulation.hpp"
#include "io/track_file.hpp"
#include "kernels/scenario.hpp"

namespace trackassoc {

// `name_or_path` is a JSON file path, or the name of an embedded scenario (data/scenarios/NAME.json,
// e.g. "seed000"). Throws InputError listing the embedded names when neither exists.
Scenario load_scenario(const std::string& name_or_path);

// A track file holding the scenario JSON, the sensors, the truth, the measurements and the tracks.
TrackFile simulation_to_track_file(const Scenario& scenario, const SimulationResult& result);

}  // namespace trackassoc
