// Local tracking (docs/design.md §4.1): each sensor turns its measurements into local tracks with its own
// filter bank. Used by `simulate` and by `trackassoc filter`.
//
// Measurement-to-track origin is taken as known: a measurement's `target` field says which
// target produced it, and clutter (target = −1) is not used for track formation. This is on
// purpose — the papers study track-to-track association, not local data association, and a
// perfect-origin local tracker isolates the association errors from local mis-association.
//
// Per sensor: one bank holds one track per target the sensor ever detects (bank order = ascending
// target id). At every scan time the whole bank is advanced by one call (predict; update where the
// target was detected, coast where it was missed). A track starts with two-point initialisation on
// its target's first two detections (Bar-Shalom et al. 2001, §5.5.3) and is reported at every
// scan from then on, coasting through missed detections. Polar measurements are converted to
// Cartesian with the linearised converted-measurement covariance (kernels/filters/kalman_converted.hpp).
// Local track numbers are a random permutation of 0..targets−1 per sensor, drawn from the
// CounterRng keyed (seed, run, shuffle tag, sensor index), so association is not trivial; the
// target id is kept in TrackTable::truth.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "kernels/core/scenario.hpp"
#include "kernels/core/types.hpp"
#include "kernels/filters/kalman_bank.hpp"

namespace trackassoc {

// A bank of local filters of one sensor, behind the filter name of LocalTrackerSpec::filter.
class LocalFilterBank {
 public:
  virtual ~LocalFilterBank() = default;
  // Advances all tracks by dt (0 = no prediction) and updates the detected ones.
  virtual void step(double dt, const PositionScan& scan) = 0;
  // Two-point initialisation of track i from Cartesian plots (z1, R1) and (z2, R2) dt apart.
  virtual void initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                          const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt) = 0;
  // Position-velocity estimate (2·d) and its covariance, as reported in a TrackTable.
  virtual void position_velocity(std::size_t i, Eigen::VectorXd& x, Eigen::MatrixXd& P) const = 0;
  // Model probabilities of track i (IMM only; empty otherwise).
  virtual std::vector<double> model_probabilities(std::size_t i) const { return {}; }
  virtual int num_models() const { return 0; }
};

// Creates the bank for `spec.filter`; throws InputError otherwise:
//   cv, ca  Kalman CV / CA with σ = spec.process_noise (kernels/filters/kalman_bank.hpp)
//   cs      "current" statistical model, CsOptions defaults (kernels/filters/cs_filter.hpp)
//   cs-nn   two parallel CS filters tuned by the trained 3-7-1 network (kernels/filters/cs_parallel.hpp)
//   imm     seed 002's IMM {cs-nn, CA σ = 5 m/s²} (kernels/filters/imm.hpp)
//   ab      alpha-beta, Kalata gains for σ = spec.process_noise (> 0) and each plot's R, with the
//           true error covariance of its estimate propagated alongside (kernels/filters/alpha_beta.hpp;
//           derivation in simulation_tracker.cpp)
std::unique_ptr<LocalFilterBank> make_local_filter_bank(const LocalTrackerSpec& spec, int spatial_dim,
                                                        std::size_t tracks);

// How a sensor's tracks end (the wide-area model, engine/simulation/simulation_widearea.hpp). The
// default keeps the model above: a track, once started, is reported at every scan to the end.
// With coast_scans = M > 0 a track is deleted at its M-th missed scan in a row (no row then), or,
// with coverage_radius R > 0, at a scan where its estimated position (after the update, or at its
// initialisation) lies beyond R from the sensor's surveyed position (no row then either); the target's next
// two plots start a new track (two-point initialisation, only if they are at most M scans apart) with a new
// local number. Numbers are then given per sensor in order of initiation (0, 1, ...; not shuffled), one per
// track.
struct TrackLifecycle {
  int32_t coast_scans = 0;
  double coverage_radius = 0.0;  // [m], 0 = unlimited
};

struct LocalTrackingResult {
  TrackTable tracks;
  // IMM model probabilities, one row per track row (row-major, num_models per row), when every
  // sensor with tracks runs the same multiple-model filter; empty otherwise.
  int num_models = 0;
  std::vector<double> model_prob;
};

// scan_times[s] lists the scan times of sensor s (same order as `sensors`); when empty, the
// distinct measurement times of that sensor are the scans.
LocalTrackingResult track_measurements(const Measurements& measurements, const std::vector<Sensor>& sensors,
                                       StateLayout layout, const LocalTrackerSpec& spec, uint64_t seed,
                                       int run, const std::vector<std::vector<double>>& scan_times = {});
// As above, sensor s running specs[s] (one per sensor, e.g. tracker_of(scenario, s)).
LocalTrackingResult track_measurements(const Measurements& measurements, const std::vector<Sensor>& sensors,
                                       StateLayout layout, std::span<const LocalTrackerSpec> specs,
                                       uint64_t seed, int run,
                                       const std::vector<std::vector<double>>& scan_times = {},
                                       std::span<const TrackLifecycle> lifecycle = {});

}  // namespace trackassoc
