// The "recorded track set" model of the simulation (Scenario::recording, kernels/core/scenario.hpp):
// what users' recordings look like, as opposed to a clean simulation where every sensor tracks
// every target for the whole run.
//
// Per (sensor s, true target j), drawn once per run from CounterRng(seed, run,
// stream_id(kRecordingWindow, s), j), always the same three draws:
//   seen     — U < p_seen: the sensor tracks this target at all; otherwise all of its plots of
//              this target are dropped (and so it has no local track);
//   window   — length L = f·duration, f = U(coverage_min, coverage_max), raised to at least
//              kMinWindowScans = 5 scan periods of the sensor (but at most the duration), start
//              U(0, duration − L), so the window [start, start + L] lies inside [0, duration].
//              Plots of the target outside the window are dropped (the local track starts late)
//              and local track rows after the window end are dropped (it ends early; between its
//              last plot and the window end the track coasts, as a real tracker does before it
//              deletes a track).
// False tracks, per sensor: N = Poisson(false_tracks · number of true targets) phantoms, drawn
// from CounterRng(seed, run, stream_id(kPhantomCount, s)). Phantom k of sensor s is a target that
// only that sensor sees: drawn like a random target (RandomTargetSpec, with its manoeuvres, but
// never in a formation) when the scenario has random targets, else uniform in the bounding box of
// the scripted targets' initial positions, speed uniform in their range of initial speeds, heading
// U(0, 2π), no process noise; streams kPhantomTrajectory / kPhantomManoeuvre (s, k). It is always
// seen, gets a window like a true target (stream kPhantomWindow (s, k)) and is detected with the
// sensor's p_detect and noise (stream kPhantomDetection (s, k)); the sensor's local tracker tracks
// it like any other target. Output: its plots in /measurements have target −1 (like clutter), its
// local track has truth −1 in /tracks, and it is not in /truth.
// Short tracks: a local track with fewer than kMinReports = 3 rows (possible when detections are
// missed in a short window) is dropped, and then the local track numbers of each sensor are
// renumbered 0..n−1 keeping their shuffled order, so numbers stay contiguous.
// With the default RecordingSpec nothing of this runs (no stream is drawn): output is unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/scenario.hpp"

namespace trackassoc {

inline constexpr int kMinWindowScans = 5;
inline constexpr int kMinReports = 3;

// The recording of one sensor: which true targets it sees, when, and its false tracks.
struct SensorRecording {
  std::vector<uint8_t> seen;                       // per true target (index into the targets)
  std::vector<double> window_start, window_end;    // per true target [s]
  std::vector<TargetTrajectory> phantoms;          // ids phantom_base + k (internal, never output)
  std::vector<double> phantom_start, phantom_end;  // per phantom [s]
  bool keeps_target(std::size_t j, double t) const {
    return seen[j] && t >= window_start[j] - 1e-9 && t <= window_end[j] + 1e-9;
  }
  bool keeps_phantom(std::size_t k, double t) const {
    return t >= phantom_start[k] - 1e-9 && t <= phantom_end[k] + 1e-9;
  }
};

struct RecordingPlan {
  bool active = false;       // false: the default RecordingSpec, nothing to do
  int32_t phantom_base = 0;  // internal ids of phantoms start here (> every true target id)
  std::vector<SensorRecording> sensors;
};

// Draws the recording of run `run`; `targets` are the true targets (simulate_trajectories).
RecordingPlan plan_recording(const Scenario& scenario, const std::vector<TargetTrajectory>& targets,
                             uint64_t seed, int run);

// Cuts the local tracks to their windows, drops short tracks, renumbers, and replaces the
// internal phantom ids by −1 in /measurements and /tracks.
void apply_recording(const RecordingPlan& plan, const Scenario& scenario,
                     const std::vector<TargetTrajectory>& targets, SimulationResult& result);

// Keeps the rows of `t` where keep[r] is set, in order.
void keep_track_rows(TrackTable& t, const std::vector<uint8_t>& keep);

// Drops local tracks with fewer than kMinReports rows and renumbers each sensor's tracks
// 0..n−1 in the order of their old numbers (steps 2 and 3 of apply_recording; the wide-area model).
void drop_short_tracks(TrackTable& tracks);

// Poisson draw: Knuth's product method for small means, the normal approximation above 30.
int poisson_draw(CounterRng& rng, double mean);

}  // namespace trackassoc
