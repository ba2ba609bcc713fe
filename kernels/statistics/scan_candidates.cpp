// Per-scan candidate index for the calibrated gate; see kernels/statistics/scan_candidates.hpp.
#include "kernels/statistics/scan_candidates.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {
namespace {

using Cell = GridCell;
constexpr auto cell_of = grid_cell_of;

// Trace of the position block of a packed covariance (the first m of D components).
double position_trace(const double* packed, int D, int m) {
  double t = 0.0;
  for (int c = 0; c < m; ++c) t += packed[packed_index(D, c, c)];
  return t;
}

void check_inputs(const AlignedTracks& a, const AlignedTracks& b, double cap, double scale) {
  require(a.dim == b.dim && a.dim % 2 == 0 && a.dim >= 2, "scan_candidate_pairs", "state dimensions differ");
  require(a.n_times == b.n_times, "scan_candidate_pairs", "numbers of common times differ");
  require(cap > 0.0 && std::isfinite(cap), "scan_candidate_pairs", "the cap must be finite and > 0");
  require(scale >= 1.0 && std::isfinite(scale), "scan_candidate_pairs", "radius_scale must be >= 1");
  for (const AlignedTracks* x : {&a, &b}) {
    const std::size_t cells = static_cast<std::size_t>(x->n_tracks()) * x->n_times;
    require(x->valid.size() == cells && x->state.size() == cells * x->dim &&
                x->cov.size() == cells * packed_size(x->dim),
            "scan_candidate_pairs",
            "aligned tracks of sensor " + std::to_string(x->sensor) + " are inconsistent");
  }
}

bool within(const AlignedTracks& a, std::size_t ca, const AlignedTracks& b, std::size_t cb, int m,
            double c2) {
  const int D = a.dim, P = packed_size(D);
  double d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    const double d = a.state[ca * D + c] - b.state[cb * D + c];
    d2 += d * d;
  }
  return d2 <= (position_trace(&a.cov[ca * P], D, m) + position_trace(&b.cov[cb * P], D, m)) * c2;
}

CandidatePairs finish(int32_t n_a, int32_t n_b, std::vector<std::pair<int32_t, int32_t>>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  CandidatePairs out;
  out.n_a = n_a;
  out.n_b = n_b;
  out.a.reserve(pairs.size());
  out.b.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    out.a.push_back(i);
    out.b.push_back(j);
  }
  return out;
}

}  // namespace

namespace {

// One pass at scan k: the tracks of `q` (queries) whose radius r_q = √(2·tr_q·c) is at least that of
// the tracks of `g` (the grid) they are checked against; cell size h. Appends (a, b) pairs.
void scan_pass(const AlignedTracks& q, const AlignedTracks& g, std::size_t k, double c2, bool q_is_a,
               std::vector<std::pair<Cell, int32_t>>& cells, std::vector<std::pair<int32_t, int32_t>>& out) {
  const int D = q.dim, m = D / 2, P = packed_size(D);
  const int32_t K = q.n_times;
  std::vector<double> radius_g(g.n_tracks(), 0.0), radius_q(q.n_tracks(), 0.0);
  std::vector<double> r;
  for (int32_t j = 0; j < g.n_tracks(); ++j) {
    const std::size_t cg = static_cast<std::size_t>(j) * K + k;
    if (!g.valid[cg]) continue;
    radius_g[j] = std::sqrt(2.0 * position_trace(&g.cov[cg * P], D, m) * c2);
    r.push_back(radius_g[j]);
  }
  if (r.empty()) return;
  std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
  double h = r[r.size() / 2];  // the median radius: most queries touch 3^m cells
  if (!(h > 0.0) || !std::isfinite(h)) h = 1e-9;
  cells.clear();
  for (int32_t j = 0; j < g.n_tracks(); ++j) {
    const std::size_t cg = static_cast<std::size_t>(j) * K + k;
    if (g.valid[cg]) cells.emplace_back(cell_of(&g.state[cg * D], m, h), j);
  }
  std::sort(cells.begin(), cells.end());
  for (int32_t i = 0; i < q.n_tracks(); ++i) {
    const std::size_t cq = static_cast<std::size_t>(i) * K + k;
    if (!q.valid[cq]) continue;
    const double rq = std::sqrt(2.0 * position_trace(&q.cov[cq * P], D, m) * c2);
    const double span_d = std::ceil(rq / h);
    auto consider = [&](int32_t j) {
      // Each pair once: from the side with the larger radius (ties: from a).
      if (q_is_a ? radius_g[j] > rq : radius_g[j] >= rq) return;
      const std::size_t cg = static_cast<std::size_t>(j) * K + k;
      if (q_is_a ? within(q, cq, g, cg, m, c2) : within(g, cg, q, cq, m, c2))
        out.emplace_back(q_is_a ? i : j, q_is_a ? j : i);
    };
    // A query wider than the whole grid (one huge covariance among small ones) reads every point
    // once instead of (2·span + 1)^m cells, so its cost is bounded by O(n_g).
    if (std::pow(2.0 * span_d + 1.0, m) > static_cast<double>(cells.size())) {
      for (const auto& e : cells) consider(e.second);
      continue;
    }
    const int64_t span = static_cast<int64_t>(span_d);
    const Cell c = cell_of(&q.state[cq * D], m, h);
    const int64_t sy = m >= 2 ? span : 0, sz = m == 3 ? span : 0;
    for (int64_t dx = -span; dx <= span; ++dx)
      for (int64_t dy = -sy; dy <= sy; ++dy)
        for (int64_t dz = -sz; dz <= sz; ++dz) {
          const Cell key{c[0] + dx, c[1] + dy, c[2] + dz};
          auto it = std::lower_bound(cells.begin(), cells.end(),
                                     std::make_pair(key, std::numeric_limits<int32_t>::min()));
          for (; it != cells.end() && it->first == key; ++it) consider(it->second);
        }
  }
}

}  // namespace

CandidatePairs scan_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                    double radius_scale) {
  check_inputs(a, b, cap, radius_scale);
  const int32_t K = a.n_times;
  const double c2 = cap * radius_scale * radius_scale;
  // Lossless: (tr_a + tr_b)·c ≤ 2·max(tr_a, tr_b)·c, so a pair within its bound is within the
  // larger of the two radii √(2·tr·c); each pair is searched from the track with the larger one
  // (two passes: a over b's grid, b over a's grid), so one wide track does not coarsen the grid.
  std::vector<std::vector<std::pair<int32_t, int32_t>>> per_scan(K);
  parallel_for_range(K, 1, [&](std::size_t lo, std::size_t hi) {
    std::vector<std::pair<Cell, int32_t>> cells;
    for (std::size_t k = lo; k < hi; ++k) {
      scan_pass(a, b, k, c2, true, cells, per_scan[k]);
      scan_pass(b, a, k, c2, false, cells, per_scan[k]);
    }
  });
  std::vector<std::pair<int32_t, int32_t>> all;
  std::size_t total = 0;
  for (const auto& v : per_scan) total += v.size();
  all.reserve(total);
  for (auto& v : per_scan) {
    all.insert(all.end(), v.begin(), v.end());
    std::vector<std::pair<int32_t, int32_t>>().swap(v);
  }
  return finish(a.n_tracks(), b.n_tracks(), all);
}

CandidatePairs scan_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                              double radius_scale) {
  check_inputs(a, b, cap, radius_scale);
  const int m = a.dim / 2;
  const int32_t K = a.n_times;
  const double c2 = cap * radius_scale * radius_scale;
  std::vector<std::pair<int32_t, int32_t>> all;
  for (int32_t i = 0; i < a.n_tracks(); ++i)
    for (int32_t j = 0; j < b.n_tracks(); ++j)
      for (int32_t k = 0; k < K; ++k) {
        const std::size_t ca = static_cast<std::size_t>(i) * K + k, cb = static_cast<std::size_t>(j) * K + k;
        if (a.valid[ca] && b.valid[cb] && within(a, ca, b, cb, m, c2)) {
          all.emplace_back(i, j);
          break;
        }
      }
  return finish(a.n_tracks(), b.n_tracks(), all);
}

CandidatePairs prune_by_position_bound(const AlignedTracks& a, const AlignedTracks& b,
                                       const CandidatePairs& pairs, const StatisticOptions& statistic) {
  if ((statistic.correlated && statistic.cross_correlation > 0.0) || statistic.common_process_noise > 0.0)
    return pairs;  // the bound is for C = P_a + P_b
  const SequentialGate gate(a.dim, statistic, a.n_times);
  if (!gate.enabled()) return pairs;
  const int D = a.dim, m = D / 2, P = packed_size(D);
  const int32_t K = a.n_times;
  const double cap = gate.cap();
  const bool calibrated = statistic.gate == GateMethod::kCalibrated;
  std::vector<uint8_t> keep(pairs.size(), 0);
  parallel_for_range(pairs.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const std::size_t i = pairs.a[q], j = pairs.b[q];
      double bound = 0.0;
      int32_t n = 0, below = 0;
      for (int32_t k = 0; k < K; ++k) {
        const std::size_t ca = i * K + k, cb = j * K + k;
        if (!a.valid[ca] || !b.valid[cb]) continue;
        ++n;
        // d_pᵀ C_pp⁻¹ d_p ≤ dᵀC⁻¹d: the position block alone (m ≤ 3, by Cholesky).
        double L[3][3] = {}, y[3] = {};
        double dp[3];
        for (int r = 0; r < m; ++r) dp[r] = a.state[ca * D + r] - b.state[cb * D + r];
        bool ok = true;
        for (int r = 0; r < m && ok; ++r)
          for (int c = 0; c <= r; ++c) {
            double v = a.cov[ca * P + packed_index(D, c, r)] + b.cov[cb * P + packed_index(D, c, r)];
            for (int t = 0; t < c; ++t) v -= L[r][t] * L[c][t];
            if (r == c) {
              if (!(v > 0.0)) {
                ok = false;
                break;
              }
              L[r][r] = std::sqrt(v);
            } else {
              L[r][c] = v / L[c][c];
            }
          }
        if (!ok) {  // leave the decision (and the error message) to the full statistic
          n = -1;
          break;
        }
        double term = 0.0;
        for (int r = 0; r < m; ++r) {
          double v = dp[r];
          for (int t = 0; t < r; ++t) v -= L[r][t] * y[t];
          y[r] = v / L[r][r];
          term += y[r] * y[r];
        }
        below += term <= cap;
        bound += std::min(term, cap);
      }
      keep[q] = n < 0 || (n > 0 && bound <= gate.threshold(n) && (!calibrated || below > 0));
    }
  });
  CandidatePairs out;
  out.n_a = pairs.n_a;
  out.n_b = pairs.n_b;
  for (std::size_t q = 0; q < pairs.size(); ++q)
    if (keep[q]) {
      out.a.push_back(pairs.a[q]);
      out.b.push_back(pairs.b[q]);
    }
  return out;
}

CandidatePairs candidate_pairs_for_gate(const AlignedTracks& a, const AlignedTracks& b,
                                        const StatisticOptions& statistic, double radius_scale) {
  if (statistic.gate == GateMethod::kCalibrated)
    return scan_candidate_pairs(a, b, SequentialGate(a.dim, statistic).cap(), radius_scale);
  return gated_candidate_pairs(a, b, CandidateOptions{statistic.gate_probability, radius_scale});
}

}  // namespace trackassoc
