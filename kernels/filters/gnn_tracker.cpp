// GNN tracker with M-of-N confirmation and single-linkage clustering (see gnn_tracker.hpp).
#include "kernels/filters/gnn_tracker.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/filters/kalman_bank.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

void GnnTrackerOptions::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  require(positive(measurement_sigma), "measurement_sigma", "expected a finite value > 0 [m]");
  require(std::isfinite(process_noise) && process_noise >= 0.0, "process_noise",
          "expected a finite value >= 0 [m/s^2]");
  require(positive(initial_speed_sigma), "initial_speed_sigma", "expected a finite value > 0 [m/s]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "gate_probability", "expected a value in (0, 1)");
  require(std::isfinite(cluster_distance) && cluster_distance >= 0.0, "cluster_distance",
          "expected a finite value >= 0 [m]");
  require(confirm_window >= 1, "confirm_window", "expected an integer >= 1");
  require(confirm_hits >= 1 && confirm_hits <= confirm_window, "confirm_hits",
          "expected an integer in [1, confirm_window]");
  require(delete_misses >= 1, "delete_misses", "expected an integer >= 1");
}

std::vector<int32_t> single_linkage_clusters(std::span<const double> x, std::span<const double> y,
                                             double distance) {
  const std::size_t m = x.size();
  std::vector<int32_t> parent(m);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  const double d2 = distance * distance;
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j) {
      const double dx = x[i] - x[j], dy = y[i] - y[j];
      if (dx * dx + dy * dy > d2) continue;
      const int32_t a = find(static_cast<int32_t>(i)), b = find(static_cast<int32_t>(j));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the cluster's first plot
    }
  std::vector<int32_t> label(m, -1), root_label(m, -1);
  int32_t next = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const int32_t r = find(static_cast<int32_t>(i));
    if (root_label[r] < 0) root_label[r] = next++;
    label[i] = root_label[r];
  }
  return label;
}

GnnTracker::GnnTracker(const GnnTrackerOptions& options) : options_(options) {
  options_.validate();
  gate_ = chi_square_quantile(options_.gate_probability, 2);
}

GnnScanSummary GnnTracker::step(double t, std::span<const double> x, std::span<const double> y,
                                std::vector<GnnTrackRow>& rows) {
  require(x.size() == y.size(), "GnnTracker::step", "x and y differ in length");
  require(std::isfinite(t) && (!started_ || t >= last_t_), "GnnTracker::step",
          "scan times must be finite and non-decreasing");
  GnnScanSummary summary;
  summary.plots = static_cast<int32_t>(x.size());

  // 1. Clusters -> centroids.
  const std::vector<int32_t> label = single_linkage_clusters(x, y, options_.cluster_distance);
  const int32_t C = label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1;
  std::vector<Eigen::Vector2d> z(C, Eigen::Vector2d::Zero());
  std::vector<int32_t> count(C, 0);
  for (std::size_t i = 0; i < label.size(); ++i) {
    z[label[i]] += Eigen::Vector2d(x[i], y[i]);
    ++count[label[i]];
  }
  for (int32_t c = 0; c < C; ++c) z[c] /= count[c];
  summary.clusters = C;

  // 2. Prediction (CV per axis: F = F1 ⊗ I₂, Q = Q1 ⊗ I₂, state x, y, vx, vy).
  const double dt = started_ ? t - last_t_ : 0.0;
  if (dt > 0.0) {
    const Eigen::MatrixXd F1 = kinematic_transition(2, dt);
    const Eigen::MatrixXd Q1 = kinematic_process_noise(2, dt, options_.process_noise);
    Eigen::Matrix4d F = Eigen::Matrix4d::Zero(), Q = Eigen::Matrix4d::Zero();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int k = 0; k < 2; ++k) {
          F(2 * a + k, 2 * b + k) = F1(a, b);
          Q(2 * a + k, 2 * b + k) = Q1(a, b);
        }
    for (Track& tr : tracks_) {
      tr.x = F * tr.x;
      tr.P = F * tr.P * F.transpose() + Q;
    }
  }
  started_ = true;
  last_t_ = t;

  // 3. Gated d² matrix and the LAP.
  const double r2 = options_.measurement_sigma * options_.measurement_sigma;
  const int32_t T = static_cast<int32_t>(tracks_.size());
  std::vector<double> cost(static_cast<std::size_t>(T) * C, std::numeric_limits<double>::infinity());
  std::vector<Eigen::Matrix2d> S_inv(T);
  for (int32_t i = 0; i < T; ++i) {
    const Eigen::Matrix2d S = tracks_[i].P.topLeftCorner<2, 2>() + r2 * Eigen::Matrix2d::Identity();
    S_inv[i] = S.inverse();
    for (int32_t c = 0; c < C; ++c) {
      const Eigen::Vector2d nu = z[c] - tracks_[i].x.head<2>();
      const double d2 = nu.dot(S_inv[i] * nu);
      if (d2 <= gate_) cost[static_cast<std::size_t>(i) * C + c] = d2;
    }
  }
  std::vector<int32_t> track_to_meas(T, -1), meas_to_track(C, -1);
  if (T > 0 && C > 0) {
    LapOptions lap;
    lap.allow_unassigned = true;
    lap.unassigned_cost = 0.5 * gate_;  // a gated pair (d² ≤ gate) is never worth leaving apart
    const LapResult res = solve_lap(cost, T, C, lap);
    for (int32_t i = 0; i < T; ++i) {
      const int32_t c = res.row_to_col[i];
      if (c >= 0 && std::isfinite(cost[static_cast<std::size_t>(i) * C + c])) {
        track_to_meas[i] = c;
        meas_to_track[c] = i;
      }
    }
  }

  // 4. Update / coast, 5. management.
  std::vector<Track> kept;
  kept.reserve(tracks_.size() + C);
  for (int32_t i = 0; i < T; ++i) {
    Track& tr = tracks_[i];
    ++tr.scans;
    const int32_t c = track_to_meas[i];
    if (c >= 0) {
      Eigen::Matrix<double, 4, 2> K = tr.P.leftCols<2>() * S_inv[i];
      tr.x += K * (z[c] - tr.x.head<2>());
      const Eigen::Matrix2d S = tr.P.topLeftCorner<2, 2>() + r2 * Eigen::Matrix2d::Identity();
      tr.P -= K * S * K.transpose();
      tr.P = 0.5 * (tr.P + tr.P.transpose());
      ++tr.hits;
      tr.misses = 0;
      ++summary.assigned;
    } else {
      ++tr.misses;
    }
    bool keep = true;
    if (tr.number < 0) {
      if (tr.hits >= options_.confirm_hits && tr.scans <= options_.confirm_window) {
        tr.number = next_number_++;
        ++summary.confirmed;
      } else if (tr.hits + (options_.confirm_window - tr.scans) < options_.confirm_hits) {
        keep = false;  // can no longer reach M hits in its first N scans
      }
    } else if (tr.misses >= options_.delete_misses) {
      keep = false;
    }
    if (keep)
      kept.push_back(tr);
    else
      ++summary.deleted;
  }
  const double v2 = options_.initial_speed_sigma * options_.initial_speed_sigma;
  // Measurements in a confirmed track's gate (the cost matrix holds d² ≤ gate there).
  std::vector<uint8_t> in_confirmed_gate(C, 0);
  if (!options_.initiate_in_gate)
    for (int32_t i = 0; i < T; ++i)
      if (tracks_[i].number >= 0)
        for (int32_t c = 0; c < C; ++c)
          in_confirmed_gate[c] |= std::isfinite(cost[static_cast<std::size_t>(i) * C + c]);
  for (int32_t c = 0; c < C; ++c) {
    if (meas_to_track[c] >= 0 || in_confirmed_gate[c]) continue;
    Track tr;
    tr.x << z[c].x(), z[c].y(), 0.0, 0.0;
    tr.P = Eigen::Vector4d(r2, r2, v2, v2).asDiagonal();
    tr.scans = 1;
    tr.hits = 1;
    if (options_.confirm_hits <= 1) tr.number = next_number_++, ++summary.confirmed;
    kept.push_back(tr);
    ++summary.started;
  }
  tracks_ = std::move(kept);
  for (const Track& tr : tracks_)
    if (tr.number >= 0) rows.push_back({tr.number, t, tr.x, tr.P});
  return summary;
}

}  // namespace trackassoc
