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
  lap.validate();
}

namespace {

// Points of the plane bucketed in square cells of side h ≥ the search radius, so the points within
// the radius of any position are in the 3×3 cells around it: a query costs O(points nearby)
// instead of O(all points). h is raised so that no axis has more than 2²⁰ cells.
class CellIndex {
 public:
  CellIndex(std::span<const double> x, std::span<const double> y, double radius) {
    const std::size_t n = x.size();
    double spread = 0.0;
    if (n > 0) {
      const auto [lx, hx] = std::minmax_element(x.begin(), x.end());
      const auto [ly, hy] = std::minmax_element(y.begin(), y.end());
      x0_ = *lx, y0_ = *ly;
      spread = std::max(*hx - *lx, *hy - *ly);
    }
    h_ = std::max({radius, spread * 0x1p-20, 1e-9});
    std::vector<int64_t> keys(n);
    for (std::size_t i = 0; i < n; ++i) keys[i] = key(cell(x[i], x0_), cell(y[i], y0_));
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0);
    std::sort(order_.begin(), order_.end(), [&](int32_t a, int32_t b) { return keys[a] < keys[b]; });
    sorted_.resize(n);
    for (std::size_t i = 0; i < n; ++i) sorted_[i] = keys[order_[i]];
  }
  // Calls fn(j) for every point j in the 3×3 cells around (px, py) (a superset of those within h).
  template <class Fn>
  void for_each_near(double px, double py, Fn&& fn) const {
    const int64_t cx = cell(px, x0_), cy = cell(py, y0_);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        const int64_t k = key(cx + dx, cy + dy);
        auto [lo, hi] = std::equal_range(sorted_.begin(), sorted_.end(), k);
        for (auto it = lo; it != hi; ++it) fn(order_[it - sorted_.begin()]);
      }
  }

 private:
  int64_t cell(double v, double origin) const {
    const double c = std::floor((v - origin) / h_);
    return static_cast<int64_t>(std::clamp(c, -4.0e6, 4.0e6));  // far outside: one border cell
  }
  static int64_t key(int64_t cx, int64_t cy) { return (cx + (int64_t{1} << 23)) * (int64_t{1} << 24) + cy; }
  double x0_ = 0, y0_ = 0, h_ = 1;
  std::vector<int32_t> order_;   // point indices by cell key
  std::vector<int64_t> sorted_;  // their keys, ascending
};

}  // namespace

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
  const CellIndex cells(x, y, distance);
  for (std::size_t i = 0; i < m; ++i)
    cells.for_each_near(x[i], y[i], [&](int32_t j) {
      if (j <= static_cast<int32_t>(i)) return;
      const double dx = x[i] - x[j], dy = y[i] - y[j];
      if (dx * dx + dy * dy > d2) return;
      const int32_t a = find(static_cast<int32_t>(i)), b = find(j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the cluster's first plot
    });
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

  // 3. Gate and LAP. Candidates (track i, measurement c, d²) with d² = νᵀS_i⁻¹ν ≤ gate, found
  // through a grid over the measurements with cells of the largest gate radius √(gate·λmax(S_i)):
  // O(T + C + candidates), not T·C; in CSR by track for the gated LAP (sparse when large and sparse).
  const double r2 = options_.measurement_sigma * options_.measurement_sigma;
  const int32_t T = static_cast<int32_t>(tracks_.size());
  std::vector<Eigen::Matrix2d> S_inv(T);
  double radius = 0.0;
  for (int32_t i = 0; i < T; ++i) {
    const Eigen::Matrix2d S = tracks_[i].P.topLeftCorner<2, 2>() + r2 * Eigen::Matrix2d::Identity();
    S_inv[i] = S.inverse();
    const double half = 0.5 * (S(0, 0) - S(1, 1)),
                 lambda_max = 0.5 * (S(0, 0) + S(1, 1)) + std::hypot(half, S(0, 1));
    radius = std::max(radius, std::sqrt(gate_ * lambda_max));
  }
  std::vector<double> zx(C), zy(C);
  for (int32_t c = 0; c < C; ++c) zx[c] = z[c].x(), zy[c] = z[c].y();
  const CellIndex cells(zx, zy, radius);
  std::vector<int32_t> row_start{0}, cand;
  std::vector<double> d2s;
  for (int32_t i = 0; i < T; ++i) {
    const Eigen::Vector2d p = tracks_[i].x.head<2>();
    cells.for_each_near(p.x(), p.y(), [&](int32_t c) {
      const Eigen::Vector2d nu = z[c] - p;
      const double d2 = nu.dot(S_inv[i] * nu);
      if (d2 <= gate_) cand.push_back(c), d2s.push_back(d2);
    });
    row_start.push_back(static_cast<int32_t>(cand.size()));
  }
  std::vector<int32_t> track_to_meas(T, -1), meas_to_track(C, -1);
  if (T > 0 && C > 0) {
    LapOptions lap;
    lap.allow_unassigned = true;
    lap.unassigned_cost = 0.5 * gate_;  // a gated pair (d² ≤ gate) is never worth leaving apart
    const LapResult res = solve_gated_lap(SparseCostView{T, C, row_start, cand, d2s}, lap, options_.lap);
    for (int32_t i = 0; i < T; ++i) {
      const int32_t c = res.row_to_col[i];  // only candidates are assigned (unassigned allowed)
      if (c >= 0) track_to_meas[i] = c, meas_to_track[c] = i;
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
  // Measurements in a confirmed track's gate (its candidates).
  std::vector<uint8_t> in_confirmed_gate(C, 0);
  if (!options_.initiate_in_gate)
    for (int32_t i = 0; i < T; ++i)
      if (tracks_[i].number >= 0)
        for (int32_t e = row_start[i]; e < row_start[i + 1]; ++e) in_confirmed_gate[cand[e]] = 1;
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
