// Synthetic recorded track sets for the sparse-path tests and benchmarks: the generator of the
// scale experiment (engine/studies/scale/experiment_scale.hpp), under the names the tests use.
#pragma once

#include "engine/studies/scale/experiment_scale.hpp"

namespace trackassoc::testing {

using SyntheticSpec = SyntheticTrackSpec;
inline TrackFile synthetic_track_file(const SyntheticSpec& spec) { return synthetic_recorded_tracks(spec); }

}  // namespace trackassoc::testing
