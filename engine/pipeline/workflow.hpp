// Glue shared by the CLI commands and the experiments: where scenarios come from, and how a
// simulation becomes a schema v1 track file.
#pragma once

#include <cstddef>
#include <string>

#include "engine/pipeline/pipeline.hpp"
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

// Checks, before any statistic is computed, that the dense tensor fits
// options.cost.memory_budget_bytes; otherwise throws an InputError naming the sizes and pointing
// to the sparse path (`--sparse`, engine/pipeline/sparse_pipeline.hpp) and to --memory-budget.
void require_dense_tensor_fits(const TrackFile& file, const PipelineOptions& options);

}  // namespace trackassoc
