// Track hygiene; see engine/pipeline/track_hygiene.hpp.
#include "engine/pipeline/track_hygiene.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

void TrackSplitOptions::validate() const {
  require(std::isfinite(min_gap_s) && min_gap_s > 0.0, "track_split.min_gap_s", "expected a gap > 0 [s]");
  require(std::isfinite(gap_factor) && gap_factor >= 1.0, "track_split.gap_factor", "expected a factor >= 1");
  require(std::isfinite(manoeuvre_sigma) && manoeuvre_sigma >= 0.0, "track_split.manoeuvre_sigma",
          "expected σ >= 0 [m/s²]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "track_split.gate_probability",
          "expected a probability in (0, 1)");
}

double continuation_statistic(const TrackTable& t, std::size_t before, std::size_t after, double q) {
  const int D = t.dim(), d = D / 2;
  const double dt = t.t[after] - t.t[before];
  const double adt = std::fabs(dt), sgn = dt < 0 ? -1.0 : 1.0;  // Q's cross term follows F's direction
  Eigen::MatrixXd F = Eigen::MatrixXd::Identity(D, D), Q = Eigen::MatrixXd::Zero(D, D);
  for (int i = 0; i < d; ++i) {
    F(i, d + i) = dt;
    Q(i, i) = q * adt * adt * adt / 3.0;
    Q(i, d + i) = Q(d + i, i) = sgn * q * adt * adt / 2.0;
    Q(d + i, d + i) = q * adt;
  }
  const Eigen::VectorXd e = t.state_at(after) - F * t.state_at(before);
  const Eigen::MatrixXd C = F * t.cov_at(before) * F.transpose() + Q + t.cov_at(after);
  return e.dot(C.ldlt().solve(e));
}

TrackSplitSummary split_recycled_tracks(TrackFile& file, const TrackSplitOptions& o) {
  o.validate();
  TrackSplitSummary summary;
  if (!o.enabled) return summary;
  TrackTable& t = file.tracks;
  std::map<std::pair<int32_t, int32_t>, std::vector<std::size_t>> rows;
  std::map<int32_t, int32_t> next_number;  // per sensor: one above its largest number
  for (std::size_t r = 0; r < t.size(); ++r) {
    rows[{t.sensor[r], t.track[r]}].push_back(r);
    int32_t& n = next_number[t.sensor[r]];
    n = std::max(n, t.track[r] + 1);
  }
  const double gate = chi_square_quantile(o.gate_probability, t.dim());
  const double q = o.manoeuvre_sigma * o.manoeuvre_sigma;
  std::vector<int32_t> source = file.source_track.empty() ? t.track : file.source_track;
  for (auto& [key, v] : rows) {
    std::stable_sort(v.begin(), v.end(), [&](std::size_t a, std::size_t b) { return t.t[a] < t.t[b]; });
    if (v.size() < 2) continue;
    std::vector<double> intervals;
    for (std::size_t i = 1; i < v.size(); ++i) intervals.push_back(t.t[v[i]] - t.t[v[i - 1]]);
    std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
    const double gap = std::max(o.min_gap_s, o.gap_factor * intervals[intervals.size() / 2]);
    int32_t number = key.second;
    for (std::size_t i = 1; i < v.size(); ++i) {
      if (t.t[v[i]] - t.t[v[i - 1]] > gap) {
        ++summary.gaps;
        if (continuation_statistic(t, v[i - 1], v[i], q) > gate) {
          ++summary.cuts;
          number = next_number[key.first]++;
        }
      }
      t.track[v[i]] = number;
    }
  }
  if (summary.cuts > 0) file.source_track = std::move(source);
  return summary;
}

}  // namespace trackassoc
