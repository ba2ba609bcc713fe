// A simulation scenario (docs/design.md §3): targets with motion segments, sensors, duration and seed.
// It is read from and written to JSON by io/scenario_json.hpp; the embedded defaults live in
// data/scenarios/. This header is plain data; the simulation is engine/simulation/simulation.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "kernels/core/enum_names.hpp"
#include "kernels/core/types.hpp"

namespace trackassoc {

enum class MotionModel {
  kConstantVelocity,      // x' = v
  kConstantAcceleration,  // v' = acceleration
  kCoordinatedTurn,       // velocity rotates at turn_rate [rad/s] in the x-y plane
  kAccelerationStep,      // constant acceleration switched on at the segment start (seed 002)
  kRandomManoeuvre,       // new random heading/speed change every manoeuvre_period (seed 003)
};
// The names of the scenario JSON's "model" key (io/scenario_json.hpp).
inline constexpr EnumName<MotionModel> kMotionModelNames[]{
    {MotionModel::kConstantVelocity, "cv"},
    {MotionModel::kConstantAcceleration, "ca"},
    {MotionModel::kCoordinatedTurn, "ct"},
    {MotionModel::kAccelerationStep, "accel_step"},
    {MotionModel::kRandomManoeuvre, "random_manoeuvre"}};
constexpr std::span<const EnumName<MotionModel>> enum_names(MotionModel) { return kMotionModelNames; }

struct MotionSegment {
  MotionModel model = MotionModel::kConstantVelocity;
  double duration = 0.0;                        // [s]
  std::array<double, 3> acceleration{0, 0, 0};  // [m/s²], CA and acceleration step
  double turn_rate = 0.0;                       // [rad/s], coordinated turn
  double manoeuvre_period = 1.0;                // [s], random manoeuvre
  double max_turn_rate = 0.0;                   // [rad/s], random manoeuvre heading change bound
  double max_speed_change = 0.0;                // [m/s per manoeuvre], random manoeuvre
  double speed_min = 0.0, speed_max = 1e9;      // [m/s], random manoeuvre speed limits
  friend bool operator==(const MotionSegment&, const MotionSegment&) = default;
};

// One scripted target. Initial state is (x, y, z, vx, vy, vz); z and vz are ignored in 2-D.
struct TargetSpec {
  int32_t id = 0;
  std::array<double, 6> initial_state{0, 0, 0, 0, 0, 0};
  std::vector<MotionSegment> segments;  // played in order; the last one lasts to the end
  friend bool operator==(const TargetSpec&, const TargetSpec&) = default;
};

// Random manoeuvres of the random targets (engine/simulation/simulation_truth.hpp has the model): straight
// legs of U(interval_min, interval_max) alternate with manoeuvres of U(duration_min, duration_max);
// a manoeuvre is a coordinated turn with probability p_turn, else an acceleration step along the
// velocity. Off unless `enabled` (in JSON: the "manoeuvres" block is present).
struct ManoeuvreSpec {
  bool enabled = false;
  double interval_min = 20.0, interval_max = 40.0;  // [s], straight legs between manoeuvres
  double duration_min = 5.0, duration_max = 15.0;   // [s], length of one manoeuvre
  double turn_rate_max = 0.05235987755982988;       // [rad/s] (3 deg/s); |rate| ∈ [max/3, max]
  double acceleration_max = 10.0;                   // [m/s²], along the velocity, any sign
  double p_turn = 0.5;                              // probability that a manoeuvre is a turn
  friend bool operator==(const ManoeuvreSpec&, const ManoeuvreSpec&) = default;
};

// Targets drawn at random per Monte Carlo run (seed 000 §4: uniform initial position in a
// rectangle, uniform speed and heading), moving with white-noise acceleration, optionally with
// random manoeuvres and in formations of group_size (line abreast, group_spacing apart).
struct RandomTargetSpec {
  int32_t count = 0;
  std::array<double, 3> area_min{0, 0, 0}, area_max{0, 0, 0};  // [m]
  double speed_min = 0.0, speed_max = 0.0;                     // [m/s]
  double heading_min = 0.0, heading_max = 6.283185307179586;   // [rad]
  double process_noise = 0.0;                                  // σ of the white-noise acceleration [m/s²]
  ManoeuvreSpec manoeuvres;                                    // off by default
  int32_t group_size = 1;                                      // targets per formation
  double group_spacing = 0.0;                                  // [m] between neighbours in a formation
  friend bool operator==(const RandomTargetSpec&, const RandomTargetSpec&) = default;
};

// The local tracker a sensor runs to turn its measurements into local tracks: Scenario::tracker for
// every sensor, unless Scenario::sensor_trackers gives that sensor its own.
struct LocalTrackerSpec {
  std::string filter = "cv";   // cv | ca | ab | cs | cs-nn | imm (docs/design.md §4.2)
  double process_noise = 1.0;  // σ of the white-noise acceleration [m/s²]
  friend bool operator==(const LocalTrackerSpec&, const LocalTrackerSpec&) = default;
};

// What a recorded track set looks like, as opposed to a clean simulation (engine/
// simulation_recording.hpp has the model and its rules). The defaults are a clean simulation:
// every sensor tracks every target for the whole run and there are no false tracks.
struct RecordingSpec {
  double p_seen = 1.0;        // per (sensor, target): probability that the sensor ever tracks it
  double coverage_min = 1.0;  // the local track covers U(coverage_min, coverage_max)·duration
  double coverage_max = 1.0;
  double false_tracks = 0.0;  // per sensor, mean number of false tracks / number of targets
  bool is_default() const { return *this == RecordingSpec{}; }
  friend bool operator==(const RecordingSpec&, const RecordingSpec&) = default;
};

// What a real sensor adds to its reports beyond noise (docs/design.md §4.10; engine/simulation/
// simulation_errors.hpp has the model): systematic registration errors, a mis-stated covariance,
// recycled track numbers and swaps at crossings. One per sensor (Scenario::sensor_errors, in the
// order of Scenario::sensors), or none. All zero (scale 1) is a clean sensor and draws nothing.
struct SensorErrors {
  double range_bias = 0.0;                     // [m], added to every measured range
  double azimuth_bias = 0.0;                   // [rad], added to every measured bearing
  double elevation_bias = 0.0;                 // [rad], added to every measured elevation (3-D)
  std::array<double, 3> site_offset{0, 0, 0};  // [m], true site − surveyed site (Sensor::position)
  double clock_offset = 0.0;                   // [s], reported time − true time of every plot
  double covariance_scale = 1.0;               // reported covariance = scale × the tracker's own
  double recycle_after = 0.0;  // [s], > 0: a track number is reused this long after its track ends
  double swap_distance = 0.0;  // [m], > 0: two local tracks whose targets pass this close swap
  bool is_default() const { return *this == SensorErrors{}; }
  friend bool operator==(const SensorErrors&, const SensorErrors&) = default;
};

// A wide-area radar network (issue 31; engine/simulation/simulation_widearea.hpp has the model):
// local tracks that break and re-initiate, and targets born and dying over hours. The coverage
// radius of each sensor is Scenario::sensor_coverage. All zero: none of it (the defaults).
struct MaskSpec {  // a scripted masking interval: `sensor` sees nothing of `target` in [start, end)
  int32_t sensor = 0, target = 0;
  double start = 0.0, end = 0.0;  // [s]
  friend bool operator==(const MaskSpec&, const MaskSpec&) = default;
};
struct WideAreaSpec {
  double edge_fraction = 0.12;  // p_detect rolls off (raised cosine) over this outer fraction of the radius
  double fade_rate = 0.0;       // [1/s] per (sensor, target): fades start as a Poisson process
  double fade_duration_min = 0.0, fade_duration_max = 0.0;  // [s] a fade lasts U(min, max)
  std::vector<MaskSpec> masks;                              // scripted fades
  int32_t coast_scans = 0;     // > 0: a local track is deleted after this many missed scans in a row
  double birth_rate = 0.0;     // [1/s] random targets born (Poisson) over (0, duration]
  double lifetime_mean = 0.0;  // [s] > 0: every random target lives Exp(mean) (the initial ones too)
  bool is_default() const { return *this == WideAreaSpec{}; }
  friend bool operator==(const WideAreaSpec&, const WideAreaSpec&) = default;
};

struct Scenario {
  std::string name = "unnamed";
  std::string description;                     // free text: where the numbers come from and why
  StateLayout layout = StateLayout::kXY_VXVY;  // 2-D or 3-D
  double duration = 100.0;                     // [s]
  double truth_step = 1.0;                     // truth sampling step [s]
  uint64_t seed = 1;
  std::vector<TargetSpec> targets;
  RandomTargetSpec random_targets;
  std::vector<Sensor> sensors;
  LocalTrackerSpec tracker;  // of every sensor without its own in sensor_trackers
  RecordingSpec recording;
  std::vector<SensorErrors> sensor_errors;  // empty, or one per sensor
  // Empty, or one per sensor (order of `sensors`): a sensor's own local tracker, or nullopt for
  // `tracker`. Real sensors run different trackers (issue 29: low and high process noise,
  // alpha-beta, IMM); their tracks then lag and smooth differently after the same manoeuvre.
  std::vector<std::optional<LocalTrackerSpec>> sensor_trackers;
  // Empty, or one per sensor: its coverage radius [m] (0 = unlimited); no plot beyond it.
  std::vector<double> sensor_coverage;
  WideAreaSpec wide_area;
  bool is_wide_area() const { return !sensor_coverage.empty() || !wide_area.is_default(); }
  friend bool operator==(const Scenario&, const Scenario&) = default;
};

// The local tracker of sensor s (index into Scenario::sensors).
inline const LocalTrackerSpec& tracker_of(const Scenario& sc, std::size_t s) {
  return s < sc.sensor_trackers.size() && sc.sensor_trackers[s] ? *sc.sensor_trackers[s] : sc.tracker;
}

}  // namespace trackassoc
