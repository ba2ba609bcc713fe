// Fused and local position RMSE against the truth: see the header.
#include "engine/fusion/fused_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "kernels/core/local_track_rows.hpp"

namespace trackassoc {

TruthInterpolator::TruthInterpolator(const TruthTable& truth) : truth_(truth) {
  for (std::size_t r = 0; r < truth.size(); ++r) rows_[truth.target[r]].push_back(r);
  for (auto& [target, v] : rows_)
    std::stable_sort(v.begin(), v.end(),
                     [&](std::size_t a, std::size_t b) { return truth.t[a] < truth.t[b]; });
}

std::optional<Eigen::VectorXd> TruthInterpolator::position(int32_t target, double t) const {
  const auto it = rows_.find(target);
  if (it == rows_.end()) return std::nullopt;
  const std::vector<std::size_t>& v = it->second;
  const auto& T = truth_.t;
  if (t < T[v.front()] || t > T[v.back()]) return std::nullopt;
  const int m = spatial_dim(truth_.layout);
  // The first sample at or after t, and the one before it.
  const auto hi = std::lower_bound(v.begin(), v.end(), t, [&](std::size_t r, double x) { return T[r] < x; });
  Eigen::VectorXd p(m);
  if (T[*hi] == t || hi == v.begin()) {
    for (int c = 0; c < m; ++c) p[c] = truth_.state[c][*hi];
    return p;
  }
  const std::size_t r0 = *(hi - 1), r1 = *hi;
  const double h = T[r1] - T[r0], s = (t - T[r0]) / h;
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  for (int c = 0; c < m; ++c)
    p[c] = h00 * truth_.state[c][r0] + h10 * h * truth_.state[m + c][r0] + h01 * truth_.state[c][r1] +
           h11 * h * truth_.state[m + c][r1];
  return p;
}

FusedAccuracy evaluate_fused(const TrackTable& tracks, const std::vector<Sensor>& sensors,
                             const TruthTable& truth, const FusedTrackRecord& fused) {
  const TruthInterpolator interp(truth);
  const int m = spatial_dim(tracks.layout);
  const int32_t S = fused.num_sensors;
  // (sensor id, track, t) → /tracks row, for the members' reports at the fused times.
  const LocalTrackRows rows = local_track_rows(tracks);

  FusedAccuracy out;
  double fused_sq = 0.0;
  std::vector<double> sensor_sq(S, 0.0);
  out.sensor_rows.assign(S, 0);
  for (std::size_t i = 0; i < fused.size(); ++i) {
    const std::optional<Eigen::VectorXd> p =
        fused.truth[i] >= 0 ? interp.position(fused.truth[i], fused.t[i]) : std::nullopt;
    if (!p) {
      ++out.rows_without_truth;
      continue;
    }
    double e2 = 0.0;
    for (int c = 0; c < m; ++c) e2 += std::pow(fused.state[c][i] - (*p)[c], 2);
    fused_sq += e2;
    ++out.fused_rows;
    const std::size_t k = static_cast<std::size_t>(fused.tuple[i]);
    for (int32_t s = 0; s < S; ++s) {
      const int32_t track = fused.tuples[k * S + s];
      if (track < 0) continue;
      const std::size_t it = rows.find({sensors[s].id, track});
      if (it == rows.size()) continue;
      const std::span<const std::size_t> v = rows.rows(it);
      const auto r = std::lower_bound(v.begin(), v.end(), fused.t[i],
                                      [&](std::size_t row, double x) { return tracks.t[row] < x; });
      if (r == v.end() || tracks.t[*r] != fused.t[i]) continue;  // no report of this member then
      double l2 = 0.0;
      for (int c = 0; c < m; ++c) l2 += std::pow(tracks.state[c][*r] - (*p)[c], 2);
      sensor_sq[s] += l2;
      ++out.sensor_rows[s];
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.fused_rmse = out.fused_rows ? std::sqrt(fused_sq / out.fused_rows) : nan;
  out.sensor_rmse.resize(S);
  for (int32_t s = 0; s < S; ++s)
    out.sensor_rmse[s] = out.sensor_rows[s] ? std::sqrt(sensor_sq[s] / out.sensor_rows[s]) : nan;
  return out;
}

void store_fused_accuracy(FusedTrackRecord& fused, const FusedAccuracy& a) {
  fused.position_rmse = a.fused_rmse;
  fused.position_rmse_rows = a.fused_rows;
  fused.sensor_position_rmse = a.sensor_rmse;
  fused.sensor_position_rmse_rows = a.sensor_rows;
}

}  // namespace trackassoc
