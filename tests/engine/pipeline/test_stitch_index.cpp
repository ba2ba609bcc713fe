// The indexed candidate search of fragment stitching (engine/pipeline/stitch_index.hpp) against the
// plain scan it replaces: for every end, every start of its time window that the pre-gate keeps
// (gap_surely_outside false), and so every start whose join cost is finite (join_cost, the gate of
// engine/pipeline/track_stitching.hpp), must be among the starts the index returns. Random scenes
// with correlated covariances, wide velocity uncertainties and non-finite reports, and starts
// placed on the boundary of the gate and on the boundary of the pre-gate, where the index's bound
// is exact (no velocity, no velocity variance, no correlation: then tr(S_pp) = τ_a + τ_b).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "engine/pipeline/stitch_index.hpp"
#include "engine/pipeline/stitch_join_cost.hpp"
#include "engine/pipeline/track_stitching.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {
namespace {

// A random positive-definite covariance: position σ of `pos` m, velocity σ of `vel` m/s, and random
// position-velocity correlations.
Eigen::MatrixXd random_covariance(int D, double pos, double vel, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int d = D / 2;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(D, D);
  for (int r = 0; r < D; ++r)
    for (int c = 0; c <= r; ++c)
      A(r, c) = r == c ? (r < d ? pos : vel) * (0.2 + u(rng)) : 0.3 * (u(rng) - 0.5) * vel;
  for (int i = 0; i < d; ++i) A(d + i, i) = (u(rng) - 0.5) * vel;  // position-velocity terms
  return A * A.transpose() + 1e-3 * Eigen::MatrixXd::Identity(D, D);
}

struct Scene {
  TrackFile file;
  std::vector<std::size_t> ends, starts;  // rows; starts in increasing time
};

// n ends over [0, 1000] s in a 1500 km square; as many starts, each after one end (start i after
// end i) by a gap of the window: for i mod 4 = 0 on the manoeuvring gate's boundary
// (m² = γ(1 − 10⁻⁶)), 1 with a random offset of up to 20 km, 2 anywhere, 3 on the pre-gate's
// boundary (end i and start i still, with a diagonal position covariance: found by bisection on
// gap_surely_outside). 5 % have a velocity σ of 300 m/s (a new track's first velocity), and two an
// infinite covariance.
Scene random_scene(StateLayout layout, int n, unsigned seed, const TrackStitchOptions& o, double gate) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Scene s;
  s.file.tracks = TrackTable(layout);
  TrackTable& t = s.file.tracks;
  const int D = t.dim(), d = D / 2;
  const double q = o.turn_sigma * o.turn_sigma;
  auto still = [&](Eigen::MatrixXd P) {  // no velocity variance, no correlation
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < D; ++c)
        if (r != c || r >= d) P(r, c) = 0.0;
    return P;
  };
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd x(D);
    for (int k = 0; k < d; ++k) x[k] = 1.5e6 * u(rng), x[d + k] = i % 4 == 3 ? 0.0 : 500.0 * (u(rng) - 0.5);
    const Eigen::MatrixXd P = random_covariance(D, 200.0, 10.0, rng);
    t.push_back(0, i, 1000.0 * u(rng), x, i % 4 == 3 ? still(P) : P, -1);
    s.ends.push_back(static_cast<std::size_t>(i));
  }
  std::vector<std::pair<double, std::size_t>> starts;
  for (int i = 0; i < n; ++i) {
    const std::size_t end = static_cast<std::size_t>(i);
    const double gap = -o.max_overlap_s + (o.max_overlap_s + o.max_gap_s) * u(rng);
    Eigen::MatrixXd P = random_covariance(D, 200.0, u(rng) < 0.05 ? 300.0 : 10.0, rng);
    if (i == 6 || i == 9) P(0, 0) = std::numeric_limits<double>::infinity();
    const int kind = i % 4;
    if (kind == 3) P = still(P);
    Eigen::VectorXd x(D);
    for (int k = 0; k < d; ++k) {
      if (kind == 2) {
        x[k] = 1.5e6 * u(rng), x[d + k] = 500.0 * (u(rng) - 0.5);
      } else {  // the end carried over the gap (same velocity), then displaced
        x[d + k] = t.state[d + k][end];
        x[k] = t.state[k][end] + gap * x[d + k];
      }
    }
    Eigen::VectorXd offset(D);
    offset.setZero();
    for (int k = 0; k < d; ++k) offset[k] = 2000.0 * (u(rng) - 0.5);  // m
    const std::size_t row = t.size();
    const double time = t.t[end] + gap;
    t.push_back(1, i, time, x + (kind == 1 ? 20.0 : 0.0) * offset, P, -1);
    auto place = [&](double scale) {
      for (int k = 0; k < d; ++k) t.state[k][row] = x[k] + scale * offset[k];
    };
    if (kind == 0) {  // m² is quadratic in the offset
      place(1.0);
      place(std::sqrt(gate * (1.0 - 1e-6) / gap_statistic(t, end, row, q).m2));
    } else if (kind == 3) {  // the largest scale the pre-gate keeps, to 10⁻¹² relative
      double in = 0.0, out = 1.0;
      for (place(out); !gap_surely_outside(t, end, row, q, gate) && out < 1e9; place(out))
        in = out, out *= 2.0;
      while (out - in > 1e-12 * out) {
        place(0.5 * (in + out));
        (gap_surely_outside(t, end, row, q, gate) ? out : in) = 0.5 * (in + out);
      }
      place(in);
    }
    starts.emplace_back(time, row);
  }
  std::sort(starts.begin(), starts.end());
  for (const auto& [time, row] : starts) s.starts.push_back(row);
  return s;
}

void expect_the_scan(StateLayout layout, unsigned seed) {
  const TrackStitchOptions o;
  const int D = state_dim(layout);
  const double gate = chi_square_quantile(o.gate_probability, D);
  const Scene s = random_scene(layout, 1500, seed, o, gate);
  const TrackTable& t = s.file.tracks;
  const StitchStartIndex index(t, s.starts, o.turn_sigma * o.turn_sigma, gate, o.max_overlap_s, o.max_gap_s);
  std::vector<int32_t> found;
  std::size_t in_windows = 0, returned = 0, kept = 0, gated = 0;
  std::array<std::size_t, 4> on_boundary{};  // of kinds 0 (gated) and 3 (kept by the pre-gate)
  for (std::size_t end : s.ends) {
    // The plain scan: every start of the window, through the pre-gate, then gated.
    const double te = t.t[end];
    std::vector<int32_t> window, pregate, scan;
    for (std::size_t p = 0; p < s.starts.size(); ++p) {
      const std::size_t start = s.starts[p];
      const double ts = t.t[start];
      if (!(ts >= te - o.max_overlap_s && ts <= te + o.max_gap_s)) continue;
      window.push_back(static_cast<int32_t>(p));
      if (gap_surely_outside(t, end, start, o.turn_sigma * o.turn_sigma, gate)) continue;
      pregate.push_back(static_cast<int32_t>(p));
      const bool mate = t.track[start] == t.track[end];
      on_boundary[3] += mate && t.track[end] % 4 == 3;
      if (!std::isfinite(join_cost(t, end, start, o, gate))) continue;
      scan.push_back(static_cast<int32_t>(p));
      on_boundary[0] += mate && t.track[end] % 4 == 0;
    }
    const auto [first, last] = index.window(te);
    ASSERT_EQ(last - first, static_cast<int32_t>(window.size())) << end;
    if (!window.empty()) {
      EXPECT_EQ(first, window.front()) << end;
    }
    index.query(t, end, found);
    EXPECT_TRUE(std::is_sorted(found.begin(), found.end())) << end;
    EXPECT_TRUE(std::includes(window.begin(), window.end(), found.begin(), found.end())) << end;
    EXPECT_TRUE(std::includes(found.begin(), found.end(), pregate.begin(), pregate.end())) << end;
    EXPECT_TRUE(std::includes(pregate.begin(), pregate.end(), scan.begin(), scan.end())) << end;
    in_windows += window.size(), returned += found.size(), kept += pregate.size(), gated += scan.size();
  }
  // Both sides are exercised: every boundary start (375 of each kind) is kept, and more; and the
  // index prunes nearly all of the windows (a 1500 km scene against a reach of ~200 km at the
  // longest gap: 0.9 % of the windows' starts returned in 2-D, 1.33 times those the pre-gate keeps).
  EXPECT_EQ(on_boundary[0], 375u);
  EXPECT_EQ(on_boundary[3], 375u);
  EXPECT_GT(gated, on_boundary[0] + 200);
  EXPECT_LT(returned * 20, in_windows);
}

TEST(StitchIndex, FindsEveryStartThePlainScanGatesIn2D) { expect_the_scan(StateLayout::kXY_VXVY, 3); }

TEST(StitchIndex, FindsEveryStartThePlainScanGatesIn3D) { expect_the_scan(StateLayout::kXYZ_VXVYVZ, 5); }

TEST(StitchIndex, StartsWithANonFiniteCovarianceAreNeverPruned) {
  const TrackStitchOptions o;
  const double gate = chi_square_quantile(o.gate_probability, 4);
  const Scene s = random_scene(StateLayout::kXY_VXVY, 300, 9, o, gate);
  const TrackTable& t = s.file.tracks;
  const StitchStartIndex index(t, s.starts, o.turn_sigma * o.turn_sigma, gate, o.max_overlap_s, o.max_gap_s);
  std::vector<int32_t> found;
  int seen = 0;
  for (std::size_t end : s.ends) {
    index.query(t, end, found);
    for (std::size_t p = 0; p < s.starts.size(); ++p) {
      const double ts = t.t[s.starts[p]], te = t.t[end];
      if (std::isfinite(t.cov[0][s.starts[p]]) || ts < te - o.max_overlap_s || ts > te + o.max_gap_s)
        continue;
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), static_cast<int32_t>(p))) << end << " " << p;
      ++seen;
    }
  }
  EXPECT_GT(seen, 0);
}

}  // namespace
}  // namespace trackassoc
