// Position accuracy of fused tracks against the ground truth (`trackassoc evaluate`): the fused
// position RMSE beside each sensor's, on the same targets over the same times.
//
//   fused:    every /fused row whose tuple has a truth target (its members agree, truth ≥ 0) and
//             whose time lies within that target's /truth samples;
//   sensor s: the reports of the tuples' members of sensor s at those rows' times (a member reports
//             at most once per time; the fused times are the members' report times).
// RMSE = sqrt(mean |p̂ − p|²) over the position components (x, y[, z]). The truth position at t is
// the cubic Hermite interpolant of the bracketing /truth samples (positions and velocities), exact
// at the samples and for constant acceleration between them, so a simulated truth step of 1 s adds
// no error worth noting (a linear interpolant would add v·ω·Δ²/8, about 1 m in a 4°/s turn at
// 200 m/s).
// Complexity: O(N log N) for N fused rows plus the truth and /tracks rows of the tuples.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "io/track_file.hpp"

namespace trackassoc {

struct FusedAccuracy {
  double fused_rmse = 0.0;  // NaN when no row was evaluated
  int32_t fused_rows = 0;
  std::vector<double> sensor_rmse;  // per /sensors column, NaN where none
  std::vector<int32_t> sensor_rows;
  int32_t rows_without_truth = 0;  // fused rows of tuples without one truth target, or outside /truth
};

// Truth positions between samples (cubic Hermite, above), one sorted series per target.
class TruthInterpolator {
 public:
  explicit TruthInterpolator(const TruthTable& truth);
  // The position of `target` at `t`; std::nullopt outside its samples or for an unknown target.
  std::optional<Eigen::VectorXd> position(int32_t target, double t) const;

 private:
  const TruthTable& truth_;
  std::map<int32_t, std::vector<std::size_t>> rows_;  // target → rows by time
};

FusedAccuracy evaluate_fused(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                             const TruthTable& truth, const FusedTrackRecord& fused);

// Stores `a` in the record's evaluation fields (/fused/<name> attrs and datasets).
void store_fused_accuracy(FusedTrackRecord& fused, const FusedAccuracy& a);

}  // namespace trackassoc
