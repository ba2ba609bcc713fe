#include "engine/pipeline/workflow.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <set>

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
  TrackFile f;
  f.created_by = created_by();
  f.scenario_json = scenario_to_json(scenario);
  f.sensors = scenario.sensors;
  f.truth = result.truth;
  f.measurements = result.measurements;
  f.tracks = result.tracks;
  return f;
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

namespace {

// Distinct local tracks of each selected sensor: the dense tensor's n1, n2, n3.
std::array<std::size_t, 3> dense_track_counts(const TrackFile& file, const PipelineOptions& options) {
  const SensorSelection sel = select_sensors(file, options, SensorRule::kThree);
  std::set<int32_t> tracks[3];
  for (std::size_t r = 0; r < file.tracks.size(); ++r)
    for (int d = 0; d < 3; ++d)
      if (file.tracks.sensor[r] == sel.ids[d]) tracks[d].insert(file.tracks.track[r]);
  return {tracks[0].size(), tracks[1].size(), tracks[2].size()};
}

double tensor_bytes(const std::array<std::size_t, 3>& n) {
  return static_cast<double>(sizeof(float)) * static_cast<double>(n[0]) * static_cast<double>(n[1]) *
         static_cast<double>(n[2]);
}

}  // namespace

void require_dense_tensor_fits(const TrackFile& file, const PipelineOptions& options) {
  const auto n = dense_track_counts(file, options);
  const double bytes = tensor_bytes(n);
  const double budget = static_cast<double>(options.cost.memory_budget_bytes);
  if (bytes <= budget) return;
  char text[400];
  std::snprintf(text, sizeof text,
                "the dense %zux%zux%zu cost tensor needs %.4g MiB, over the memory budget of %.4g MiB "
                "(--memory-budget); rerun with --sparse (gated candidate tuples, solved per connected "
                "component), or raise --memory-budget",
                n[0], n[1], n[2], bytes / 1048576.0, budget / 1048576.0);
  throw InputError(text);
}

}  // namespace trackassoc
