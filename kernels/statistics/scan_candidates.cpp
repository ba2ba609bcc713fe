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
  a.check_layout("scan_candidate_pairs");
  b.check_layout("scan_candidate_pairs");
}

// |d_p|² ≤ (tr P_a,pp + tr P_b,pp)·c for positions xa, xb and position traces tra, trb.
bool within_points(const double* xa, double tra, const double* xb, double trb, int m, double c2) {
  double d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    const double d = xa[c] - xb[c];
    d2 += d * d;
  }
  return d2 <= (tra + trb) * c2;
}

bool within(const AlignedTracks& a, int64_t ca, const AlignedTracks& b, int64_t cb, int m, double c2) {
  const int D = a.dim;
  return within_points(a.state_at(ca), position_trace(a.cov_at(ca), D, m), b.state_at(cb),
                       position_trace(b.cov_at(cb), D, m), m, c2);
}

// The tracks valid at each common time, ascending: tracks at(k). Built from the spans, O(Σ spans + K).
struct ValidByTime {
  std::vector<int64_t> offset;  // K + 1
  std::vector<int32_t> track;
  std::span<const int32_t> at(std::size_t k) const {
    return {track.data() + offset[k], static_cast<std::size_t>(offset[k + 1] - offset[k])};
  }
};

ValidByTime valid_by_time(const AlignedTracks& x) {
  ValidByTime out;
  out.offset.assign(static_cast<std::size_t>(x.n_times) + 1, 0);
  auto each_valid = [&](auto&& fn) {
    for (int32_t i = 0; i < x.n_tracks(); ++i) {
      const AlignedTracks::Span sp = x.span(i);
      for (int32_t k = sp.begin; k < sp.end; ++k)
        if (x.valid[x.cell_base(i) + k]) fn(i, k);
    }
  };
  each_valid([&](int32_t, int32_t k) { ++out.offset[k + 1]; });
  for (std::size_t k = 0; k + 1 < out.offset.size(); ++k) out.offset[k + 1] += out.offset[k];
  out.track.resize(static_cast<std::size_t>(out.offset.back()));
  std::vector<int64_t> next(out.offset.begin(), out.offset.end() - 1);
  each_valid([&](int32_t i, int32_t k) { out.track[next[k]++] = i; });
  return out;
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

// One pass at scan k: the tracks of `q` (queries, q_at: those valid at k) whose radius
// r_q = √(2·tr_q·c) is at least that of the tracks of `g` (the grid, g_at) they are checked against;
// cell size h. Appends (a, b) pairs.
// Scratch of one scan's grid, by position p in g_at (ascending tracks): cell, position trace, radius.
struct GridScratch {
  std::vector<std::pair<Cell, int32_t>> cells;  // (grid cell, p), sorted
  std::vector<int64_t> cell;
  std::vector<double> trace, radius;
};

void scan_pass(const AlignedTracks& q, std::span<const int32_t> q_at, const AlignedTracks& g,
               std::span<const int32_t> g_at, int32_t k, double c2, bool q_is_a, GridScratch& scratch,
               std::vector<std::pair<int32_t, int32_t>>& out) {
  if (g_at.empty() || q_at.empty()) return;
  const int D = q.dim, m = D / 2;
  auto& [cells, cell_g, trace_g, radius_g] = scratch;
  cell_g.resize(g_at.size());
  trace_g.resize(g_at.size());
  radius_g.resize(g_at.size());
  for (std::size_t p = 0; p < g_at.size(); ++p) {
    cell_g[p] = g.cell_base(g_at[p]) + k;
    trace_g[p] = position_trace(g.cov_at(cell_g[p]), D, m);
    radius_g[p] = std::sqrt(2.0 * trace_g[p] * c2);
  }
  std::vector<double> r(radius_g);
  std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
  double h = r[r.size() / 2];  // the median radius: most queries touch 3^m cells
  if (!(h > 0.0) || !std::isfinite(h)) h = 1e-9;
  cells.clear();
  for (std::size_t p = 0; p < g_at.size(); ++p)
    cells.emplace_back(cell_of(g.state_at(cell_g[p]), m, h), static_cast<int32_t>(p));
  std::sort(cells.begin(), cells.end());  // by cell, then track (p ascends with the track)
  for (const int32_t i : q_at) {
    const int64_t cq = q.cell_base(i) + k;
    const double* xq = q.state_at(cq);
    const double trace_q = position_trace(q.cov_at(cq), D, m);
    const double rq = std::sqrt(2.0 * trace_q * c2);
    const double span_d = std::ceil(rq / h);
    auto consider = [&](int32_t p) {
      // Each pair once: from the side with the larger radius (ties: from a).
      if (q_is_a ? radius_g[p] > rq : radius_g[p] >= rq) return;
      const double* xg = g.state_at(cell_g[p]);
      if (q_is_a ? within_points(xq, trace_q, xg, trace_g[p], m, c2)
                 : within_points(xg, trace_g[p], xq, trace_q, m, c2))
        out.emplace_back(q_is_a ? i : g_at[p], q_is_a ? g_at[p] : i);
    };
    // A query wider than the whole grid (one huge covariance among small ones) reads every point
    // once instead of (2·span + 1)^m cells, so its cost is bounded by O(n_g).
    if (std::pow(2.0 * span_d + 1.0, m) > static_cast<double>(cells.size())) {
      for (const auto& e : cells) consider(e.second);
      continue;
    }
    const int64_t span = static_cast<int64_t>(span_d);
    const Cell c = cell_of(xq, m, h);
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
  // Each scan's tracks come from the spans (valid_by_time), so a scan costs its own tracks only.
  const ValidByTime va = valid_by_time(a), vb = valid_by_time(b);
  std::vector<std::vector<std::pair<int32_t, int32_t>>> per_scan(K);
  parallel_for_range(K, 1, [&](std::size_t lo, std::size_t hi) {
    GridScratch scratch;
    for (std::size_t k = lo; k < hi; ++k) {
      const auto kk = static_cast<int32_t>(k);
      scan_pass(a, va.at(k), b, vb.at(k), kk, c2, true, scratch, per_scan[k]);
      scan_pass(b, vb.at(k), a, va.at(k), kk, c2, false, scratch, per_scan[k]);
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
  const double c2 = cap * radius_scale * radius_scale;
  std::vector<std::pair<int32_t, int32_t>> all;
  for (int32_t i = 0; i < a.n_tracks(); ++i)
    for (int32_t j = 0; j < b.n_tracks(); ++j)
      for (int32_t k = 0; k < a.n_times; ++k) {  // every k, the naive peer (cell() −1 off the span)
        const int64_t ca = a.cell(i, k), cb = b.cell(j, k);
        if (ca >= 0 && cb >= 0 && a.valid[ca] && b.valid[cb] && within(a, ca, b, cb, m, c2)) {
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
  const SequentialGate gate(a.dim, statistic, std::min({a.n_times, longest_span(a), longest_span(b)}));
  if (!gate.enabled()) return pairs;
  const int D = a.dim, m = D / 2;
  const double cap = gate.cap();
  const bool calibrated = statistic.gate == GateMethod::kCalibrated;
  std::vector<uint8_t> keep(pairs.size(), 0);
  parallel_for_range(pairs.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const int32_t i = pairs.a[q], j = pairs.b[q];
      double bound = 0.0;
      int32_t n = 0, below = 0;
      const AlignedTracks::Span both = common_span(a.span(i), b.span(j));
      const int64_t base_a = a.cell_base(i), base_b = b.cell_base(j);
      for (int32_t k = both.begin; k < both.end; ++k) {
        const int64_t ca = base_a + k, cb = base_b + k;
        if (!a.valid[ca] || !b.valid[cb]) continue;
        ++n;
        // d_pᵀ C_pp⁻¹ d_p ≤ dᵀC⁻¹d: the position block alone (m ≤ 3, by Cholesky).
        double L[3][3] = {}, y[3] = {};
        double dp[3];
        const double *xa = a.state_at(ca), *xb = b.state_at(cb), *pa = a.cov_at(ca), *pb = b.cov_at(cb);
        for (int r = 0; r < m; ++r) dp[r] = xa[r] - xb[r];
        bool ok = true;
        for (int r = 0; r < m && ok; ++r)
          for (int c = 0; c <= r; ++c) {
            double v = pa[packed_index(D, c, r)] + pb[packed_index(D, c, r)];
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
