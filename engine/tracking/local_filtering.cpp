// trackassoc filter (see local_filtering.hpp).
#include "engine/tracking/local_filtering.hpp"

#include "engine/simulation/simulation_tracker.hpp"
#include "io/scenario_json.hpp"
#include "io/track_file.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

FilterFileSummary filter_track_file(const FilterFileOptions& o) {
  TrackFile file = read_track_file(o.input);
  if (!file.measurements || file.measurements->size() == 0)
    throw InputError(o.input + ": /measurements: missing or empty; `filter` needs measurements to track");
  LocalTrackerSpec spec;
  StateLayout layout = file.tracks.layout;
  if (!file.scenario_json.empty()) {
    const Scenario sc = parse_scenario_json(file.scenario_json, o.input + ":/scenario");
    spec = sc.tracker;
    layout = sc.layout;
  }
  track_validation::check_measurement_noise(o.input, *file.measurements, file.sensors,
                                            layout == StateLayout::kXYZ_VXVYVZ);
  spec.filter = o.filter;
  if (o.process_noise >= 0.0) spec.process_noise = o.process_noise;
  if (spec.filter == "ab" && !(spec.process_noise > 0.0))
    throw InputError("--process-noise: the alpha-beta filter's Kalata gains need σ > 0 [m/s²], got " +
                     std::to_string(spec.process_noise));
  LocalTrackingResult r = track_measurements(*file.measurements, file.sensors, layout, spec, o.seed, o.run);
  file.tracks = r.tracks;
  file.associations.clear();
  file.metrics.clear();
  if (r.num_models > 0)
    write_track_file(o.output, file,
                     TrackModelProbabilities{std::move(r.model_prob), r.num_models, "cs-nn,ca"});
  else
    write_track_file(o.output, file);
  return {file.measurements->size(), file.sensors.size(), file.tracks.size()};
}

}  // namespace trackassoc
