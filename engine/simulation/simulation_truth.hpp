// Ground-truth trajectories of the simulation (docs/design.md §4.1): a target's motion as a list of
// pieces, each with closed-form kinematics, so truth is exact at any sensor time (no integration
// error, no dependence on the truth sampling step).
//
// Pieces: constant acceleration (CV when a = 0, CA, acceleration step) and coordinated turn
// (velocity rotating at ω in the x-y plane, constant vertical velocity).
// Motion models of kernels/core/scenario.hpp map onto pieces as follows:
//   kConstantVelocity / kConstantAcceleration / kAccelerationStep: one CA piece with the segment's
//     acceleration (0 for CV). An acceleration step is a CA segment that follows another segment.
//   kCoordinatedTurn: one turn piece at turn_rate.
//   kRandomManoeuvre: one piece per manoeuvre_period. At each manoeuvre the heading turns by
//     U(−max_turn_rate, max_turn_rate)·period and the speed changes by U(−max_speed_change,
//     max_speed_change), clamped to [speed_min, speed_max]; the piece is the constant horizontal
//     acceleration that takes the old velocity to the new one over the period (position and
//     velocity stay continuous).
// RandomTargetSpec targets: initial position U(area), speed U(speed_min, speed_max), heading
// U(heading_min, heading_max) in the x-y plane, then piecewise-constant acceleration N(0, σ²)
// per axis over every truth_step — exactly the discrete white-noise acceleration model of the
// CV Kalman filter (Bar-Shalom et al. 2001, §6.3.2), so a CV filter with the same σ and a scan
// period equal to truth_step is consistent.
// Random manoeuvres (RandomTargetSpec::manoeuvres, off by default): straight legs of length
// U(interval_min, interval_max) — white-noise acceleration as above, one N(0, σ²) draw per axis
// per truth_step (a leg end cuts a step short) — alternate with manoeuvres of length
// U(duration_min, duration_max), starting with a leg. A manoeuvre is noise-free: with probability
// p_turn a coordinated turn at rate ±U(turn_rate_max/3, turn_rate_max) (random sign), else a
// constant acceleration a·v/|v| along the velocity at the manoeuvre's start, a = U(−a_max, a_max)
// clamped so that the speed stays in [0.5·speed_min, max(1.5·speed_max, 0.5·speed_min)] (the speed
// is linear in time during the step, so clamping the end speed bounds all of it). The manoeuvre
// draws come from their own stream (kRandomManoeuvre), so switching them on leaves the initial
// states unchanged.
// Formations (group_size m > 1): random targets are drawn in groups of m (the last group may be
// smaller) that share one reference trajectory (initial state, noise, manoeuvres: the draws of
// target k above are those of group k). Member j of a group sits at the offset
// (j − (m−1)/2)·group_spacing perpendicular to the initial heading (line abreast), and the group
// moves as a rigid body: in straight flight and acceleration steps every member has the
// reference's velocity; in a turn the whole line turns about the reference's turn centre at the
// same rate, so the offset rotates with the heading (an outer member flies faster; its velocity
// steps by ω·offset at the turn's entry and exit). The distance between members is therefore
// constant at all times, with or without process noise. Ids: first_id + j within the group.
// With m = 1 and no manoeuvres the draws and pieces are exactly those of random_trajectory.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/core/scenario.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

// Purposes of the simulation's random streams: CounterRng(seed, run, stream_id(tag, index), sub).
enum class SimulationStream : uint64_t {
  kTargetManoeuvre = 1,
  kRandomTarget = 2,
  kDetection = 3,
  kClutter = 4,
  kShuffle = 5,
  // The recording model (engine/simulation/simulation_recording.hpp) and random manoeuvres; new streams only,
  // so the streams above, and scenarios that do not use these features, are unchanged.
  kRandomManoeuvre = 6,    // per random-target group: manoeuvre times and kinds
  kRecordingWindow = 7,    // per (sensor, target): seen or not, coverage window
  kPhantomCount = 8,       // per sensor: number of false tracks
  kPhantomTrajectory = 9,  // per (sensor, false track): its trajectory
  kPhantomManoeuvre = 10,  // per (sensor, false track): its manoeuvres
  kPhantomWindow = 11,     // per (sensor, false track): its coverage window
  kPhantomDetection = 12,  // per (sensor, false track): its detections and noise
  // The wide-area model (engine/simulation/simulation_widearea.hpp).
  kFade = 13,     // per (sensor, target or phantom): fade start times and durations
  kBirth = 14,    // per run: the birth times of the born targets
  kLifetime = 15  // per random target (group) or born target: its lifetime
};
inline uint64_t stream_id(SimulationStream tag, uint64_t index) {
  return (static_cast<uint64_t>(tag) << 40) | index;
}

struct Kinematics {
  std::array<double, 3> p{0, 0, 0}, v{0, 0, 0}, a{0, 0, 0};
};

struct TrajectoryPiece {
  double t0 = 0, t1 = 0;
  Kinematics start;      // position and velocity at t0 (start.a = acceleration of a CA piece)
  double turn_rate = 0;  // ≠ 0: coordinated turn
};

class TargetTrajectory {
 public:
  int32_t id = 0;
  std::vector<TrajectoryPiece> pieces;  // contiguous, sorted, covering [born, min(dies, duration)]
  // The target exists in [born, dies] (wide-area turnover); always, by default.
  double born = 0.0, dies = std::numeric_limits<double>::infinity();
  bool alive(double t) const { return t >= born - 1e-9 && t <= dies + 1e-9; }
  Kinematics at(double t) const;  // beyond the last piece: extrapolated
  // The position at t for times visited in increasing order: `piece` is a cursor kept by the
  // caller (start at 0), so a sweep costs O(pieces + times) instead of a search per time.
  std::array<double, 3> position_at(double t, std::size_t& piece) const;
  // Appends a piece of length `duration` starting from the end of the previous one.
  void append(double duration, const std::array<double, 3>& accel, double turn_rate);
};

// `rng` supplies the random manoeuvres; spatial_dim 2 zeroes z motion.
TargetTrajectory scripted_trajectory(const TargetSpec& spec, double duration, int spatial_dim,
                                     CounterRng& rng);
TargetTrajectory random_trajectory(const RandomTargetSpec& spec, int32_t id, double duration, double step,
                                   int spatial_dim, CounterRng& rng);
// One formation of `members` random targets with ids first_id, first_id + 1, ... (see above);
// `rng` draws the reference trajectory, `manoeuvre_rng` its manoeuvres.
std::vector<TargetTrajectory> random_group_trajectories(const RandomTargetSpec& spec, int32_t first_id,
                                                        int members, double duration, double step,
                                                        int spatial_dim, CounterRng& rng,
                                                        CounterRng& manoeuvre_rng);

// The trajectories of all targets of Monte Carlo run `run` (scripted first, then the random
// targets with ids after the largest scripted id), as used by simulate(). Validates the scenario.
std::vector<TargetTrajectory> simulate_trajectories(const Scenario& scenario, uint64_t seed, int run);

// The measurements of sensor `sensor_index` for one run (the measurement model of
// engine/simulation/simulation.cpp) and its scan times. Used by simulate() and the seed 002 experiment.
struct SensorMeasurements {
  Measurements m;
  std::vector<double> scans;
};
// With `recording` (engine/simulation/simulation_recording.hpp), plots of targets outside their window or
// not seen are dropped (their random draws are still made, so the other plots are unchanged) and
// the sensor's phantoms are measured too, with their internal ids as `target`.
struct SensorRecording;
SensorMeasurements simulate_sensor(const Scenario& scenario, std::size_t sensor_index,
                                   const std::vector<TargetTrajectory>& targets, uint64_t seed, int run,
                                   const SensorRecording* recording = nullptr);

}  // namespace trackassoc
