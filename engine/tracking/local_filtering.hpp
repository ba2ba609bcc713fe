// `trackassoc filter`: a track file's /measurements turned into /tracks by a filter bank, one bank
// per sensor (engine/simulation/simulation_tracker.hpp: perfect measurement-to-track origin from
// /measurements/target, clutter ignored, two-point initialisation, shuffled local track numbers).
// Everything else of the input is kept except /associations and /metrics, which described the old
// tracks. The filter's spec (process noise, ...) is the file's scenario's tracker when it records
// one, else LocalTrackerSpec's defaults; --filter runs on every sensor, so a sensor's own tracker in
// the scenario (Scenario::sensor_trackers) is not used. The IMM banks' model probabilities go to
// /tracks/model_prob with /tracks/models naming the columns (io/track_file.hpp), in the same
// atomic write as the rest of the file.
#pragma once

#include <cstdint>
#include <string>

namespace trackassoc {

struct FilterFileOptions {
  std::string input, output;
  std::string filter = "cv";    // cv | ca | ab | cs | cs-nn | imm (make_local_filter_bank)
  double process_noise = -1.0;  // σ of cv/ca/ab [m/s²]; < 0: the file's scenario's (else 1)
  uint64_t seed = 1;            // with `run`, keys the track-number shuffle
  int run = 0;
};

struct FilterFileSummary {
  std::size_t measurements = 0, sensors = 0, track_reports = 0;
};

// Reads `input` (InputError when it has no measurements, or their noise is not usable), filters,
// writes `output`.
FilterFileSummary filter_track_file(const FilterFileOptions& options);

}  // namespace trackassoc
