// The wide-area network model of the simulation (issue 31, docs/design.md §4.10): tens of radars,
// each seeing only the targets within its coverage, over hours, with targets born and dying and
// each radar's track of a target breaking where it fades or is masked. Fields: Scenario::
// sensor_coverage and Scenario::wide_area (kernels/core/scenario.hpp); a scenario without them is
// simulated exactly as before (none of this runs, no stream is drawn).
//
// Coverage: sensor s with radius R > 0 detects a target at true range r (from its true site) with
//   p_D(r) = p_detect · g(r),  g = 1 for r ≤ (1 − f)R,  ½(1 + cos(π (r − (1 − f)R) / (f R))) up to R,
//   0 beyond (a raised-cosine roll-off over the outer fraction f = edge_fraction), so no plot lies
//   beyond R. Its clutter is uniform in range over [0, R] (clutter needs a radius in this model).
// Fades: per (sensor, target) a renewal process over the target's life, gaps Exp(fade_rate) and
//   durations U(fade_duration_min, fade_duration_max), drawn in time order from CounterRng(seed,
//   run, stream_id(kFade, s), j) (phantoms: index targets + k); plus the scripted masks. Faded or
//   masked, the sensor has no plot of the target.
// Plots: at each scan of sensor s, for each target alive then (and kept by the recording model,
//   when there is one), within R and not faded, one uniform (detected when < p_D(r)) and the noise
//   normals of the clean model are drawn from the (sensor, target) stream kDetection (phantoms:
//   kPhantomDetection), then the plot is made as in engine/simulation/simulation.cpp, registration
//   errors included. Outside coverage or faded nothing is drawn.
// Local tracks (engine/simulation/simulation_tracker.hpp, TrackLifecycle): with coast_scans = M, a
//   track is deleted at its M-th missed scan in a row, or as soon as its estimate lies beyond R
//   (a radar drops what leaves its coverage); the target's next plots start a new track (two-point
//   initialisation) under a NEW local number, while /tracks/truth stays the target's. Numbers are
//   given per sensor in order of initiation. Then tracks of fewer than kMinReports rows are
//   dropped and the numbers made contiguous (drop_short_tracks).
// Turnover: with lifetime_mean L > 0 every random target lives Exp(L) from its birth (stream
//   kLifetime, index = its random-target stream index; a formation shares its reference's life).
//   The `count` initial targets are born at 0 (with count = birth_rate·L the population is
//   stationary: exponential lives are memoryless); births form a Poisson process of rate
//   birth_rate over (0, duration] (stream kBirth), each a single random target (RandomTargetSpec,
//   never in a formation; streams kRandomTarget / kRandomManoeuvre / kLifetime at index count + b),
//   ids following the initial ones in order of birth. A target exists in [born, dies]: truth rows
//   and plots only then. The expected number alive at t is
//     N(t) = count·e^(−t/L) + birth_rate·L·(1 − e^(−t/L)).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_recording.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/scenario.hpp"

namespace trackassoc {

// Throws InputError naming the field (scenario.wide_area.*, scenario.sensors[i].coverage_radius).
void validate_wide_area(const Scenario& scenario);

// Sensor s's coverage radius [m]; 0 = unlimited.
double coverage_of(const Scenario& scenario, std::size_t s);

// The detection roll-off g(r) above (1 inside (1 − f)R, 0 beyond R; 1 everywhere when R = 0).
double coverage_gain(double range, double radius, double edge_fraction);

// Lifetime of random target (group) stream `index` of run `run` (+∞ without turnover).
double draw_lifetime(const Scenario& scenario, uint64_t seed, int run, uint64_t index);

// The targets born during the run, ids first_id, first_id + 1, ... in order of birth.
std::vector<TargetTrajectory> born_targets(const Scenario& scenario, uint64_t seed, int run,
                                           int32_t first_id);

// Expected target-seconds of existence over the run (size estimates), and the fraction of a
// target's time that sensor s can see (its coverage disc over the random-target area, at most 1).
double expected_target_seconds(const Scenario& scenario);
double coverage_share(const Scenario& scenario, std::size_t s);

// The plots of sensor s in the wide-area model (what simulate_sensor does for such scenarios).
SensorMeasurements simulate_sensor_wide(const Scenario& scenario, std::size_t s,
                                        const std::vector<TargetTrajectory>& targets, uint64_t seed, int run,
                                        const SensorRecording* recording);

}  // namespace trackassoc
