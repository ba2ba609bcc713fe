// Ground-truth trajectories of the simulation (DESIGN §4.1): a target's motion as a list of
// pieces, each with closed-form kinematics, so truth is exact at any sensor time (no integration
// error, no dependence on the truth sampling step).
//
// Pieces: constant acceleration (CV when a = 0, CA, acceleration step) and coordinated turn
// (velocity rotating at ω in the x-y plane, constant vertical velocity).
// Motion models of kernels/scenario.hpp map onto pieces as follows:
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
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/random.hpp"
#include "kernels/scenario.hpp"
#include "kernels/types.hpp"

namespace trackassoc {

// Purposes of the simulation's random streams: CounterRng(seed, run, stream_id(tag, index), sub).
enum class SimulationStream : uint64_t {
  kTargetManoeuvre = 1,
  kRandomTarget = 2,
  kDetection = 3,
  kClutter = 4,
  kShuffle = 5
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
  std::vector<TrajectoryPiece> pieces;  // contiguous, sorted, covering [0, duration]
  Kinematics at(double t) const;        // beyond the last piece: extrapolated
  // Appends a piece of length `duration` starting from the end of the previous one.
  void append(double duration, const std::array<double, 3>& accel, double turn_rate);
};

// `rng` supplies the random manoeuvres; spatial_dim 2 zeroes z motion.
TargetTrajectory scripted_trajectory(const TargetSpec& spec, double duration, int spatial_dim,
                                     CounterRng& rng);
TargetTrajectory random_trajectory(const RandomTargetSpec& spec, int32_t id, double duration, double step,
                                   int spatial_dim, CounterRng& rng);

// The trajectories of all targets of Monte Carlo run `run` (scripted first, then the random
// targets with ids after the largest scripted id), as used by simulate(). Validates the scenario.
std::vector<TargetTrajectory> simulate_trajectories(const Scenario& scenario, uint64_t seed, int run);

// The measurements of sensor `sensor_index` for one run (the measurement model of
// engine/simulation.cpp) and its scan times. Used by simulate() and the seed 002 experiment.
struct SensorMeasurements {
  Measurements m;
  std::vector<double> scans;
};
SensorMeasurements simulate_sensor(const Scenario& scenario, std::size_t sensor_index,
                                   const std::vector<TargetTrajectory>& targets, uint64_t seed, int run);

}  // namespace trackassoc
