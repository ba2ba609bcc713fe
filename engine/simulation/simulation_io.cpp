#include "engine/simulation/simulation_io.hpp"

#include <filesystem>

#include "engine/embedded_data.hpp"
#include "engine/version.hpp"
#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

Scenario load_scenario(const std::string& name_or_path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(name_or_path, ec)) return read_scenario_file(name_or_path);
  if (auto text = embedded_scenario(name_or_path))
    return parse_scenario_json(*text, "embedded:" + name_or_path);
  std::string names;
  for (const auto& s : embedded_scenarios()) names += (names.empty() ? "" : ", ") + std::string(s.name);
  throw InputError("--scenario: '" + name_or_path + "' is neither a file nor an embedded scenario (" + names +
                   ")");
}

TrackFile simulation_to_track_file(const Scenario& scenario, const SimulationResult& result) {
  return simulation_to_track_file(scenario, SimulationResult(result));  // a copy, then the move below
}

TrackFile simulation_to_track_file(const Scenario& scenario, SimulationResult&& result) {
  TrackFile f;
  f.created_by = created_by();
  f.scenario_json = scenario_to_json(scenario);
  f.sensors = scenario.sensors;
  f.truth = std::move(result.truth);
  f.measurements = std::move(result.measurements);
  f.tracks = std::move(result.tracks);
  return f;
}

}  // namespace trackassoc
