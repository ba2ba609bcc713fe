// Per-scan candidate index for the calibrated gate; see kernels/statistics/scan_candidates.hpp.
#include "kernels/statistics/scan_candidates.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/radix_sort.hpp"

namespace trackassoc {
namespace {

using Cell = GridCell;
constexpr auto cell_of = grid_cell_of;

void check_inputs(const AlignedTracks& a, const AlignedTracks& b, double cap, double scale) {
  require(a.dim == b.dim && a.dim % 2 == 0 && a.dim >= 2, "scan_candidate_pairs", "state dimensions differ");
  require(a.n_times == b.n_times, "scan_candidate_pairs", "numbers of common times differ");
  require(cap > 0.0 && std::isfinite(cap), "scan_candidate_pairs", "the cap must be finite and > 0");
  require(scale >= 1.0 && std::isfinite(scale), "scan_candidate_pairs", "radius_scale must be >= 1");
  a.check_layout("scan_candidate_pairs");
  b.check_layout("scan_candidate_pairs");
}

// The position block of a packed covariance of dimension D (positions the first m ≤ 3
// components), upper triangle by rows in 6 doubles: m = 2 (xx, xy, yy, ...), m = 3 (xx, xy, xz,
// yy, yz, zz).
constexpr int kPositionBlock = 6;
void position_block(const double* packed, int D, int m, double* out) {
  int k = 0;
  for (int r = 0; r < m; ++r)
    for (int c = r; c < m; ++c) out[k++] = packed[packed_index(D, r, c)];
}

// A bound on the largest eigenvalue of a position block, by a relative 10⁻⁸ more so that the circle
// below is never inside the ellipse's 10⁻⁹: its largest Gershgorin row sum P_ii + Σ_{j≠i} |P_ij|
// (a bound for any symmetric block), or its trace when that is smaller and the block is positive
// semi-definite (every principal minor ≥ 0: only then is the trace a bound; a block that is not,
// beside a larger one, can still sum to a positive definite C); m = 1: the variance. A NaN entry
// gives the trace, as before this bound (a NaN on the diagonal, NaN: never within; elsewhere the
// ellipse test passes the pair to the statistic, which reports it). The trace alone is m times
// the largest eigenvalue for an isotropic covariance: in 3-D the search radius √3 and the
// searched volume 5.2 times too large (the scale study's tracks, σ = 150 m on every axis,
// docs/performance.md "Session 33").
double position_spread(const double* block, int m) {
  constexpr double kWiden = 1.0 + 1e-8;
  if (m == 1) return block[0] * kWiden;
  if (m == 2) {
    const double xx = block[0], xy = block[1], yy = block[2], trace = xx + yy;
    if (std::isnan(trace + xy)) return trace;
    const double gershgorin = std::max(xx, yy) + std::abs(xy);
    const bool semi_definite = xx >= 0.0 && yy >= 0.0 && xx * yy >= xy * xy;
    return (trace < gershgorin && semi_definite ? trace : gershgorin) * kWiden;
  }
  const double xx = block[0], xy = block[1], xz = block[2], yy = block[3], yz = block[4], zz = block[5];
  const double trace = xx + yy + zz;
  if (std::isnan(trace + xy + xz + yz)) return trace;
  const double gershgorin = std::max(
      {xx + std::abs(xy) + std::abs(xz), yy + std::abs(xy) + std::abs(yz), zz + std::abs(xz) + std::abs(yz)});
  if (!(trace < gershgorin)) return gershgorin * kWiden;  // (the usual case; no minors needed)
  const double det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  const bool semi_definite = xx >= 0.0 && yy >= 0.0 && zz >= 0.0 && xx * yy >= xy * xy &&
                             xx * zz >= xz * xz && yy * zz >= yz * yz && det >= 0.0;
  return (semi_definite ? trace : gershgorin) * kWiden;
}

// d_pᵀ C_pp⁻¹ d_p ≤ c2 for C_pp = the sum of the position blocks pa, pb, by the adjugate (m = 2
// or 3, no square root): a superset, by a relative 10⁻⁹, of the prune's Cholesky test
// (kernels/statistics/gate_candidates.cpp), so that nothing the prune counts within is missed.
// True when C_pp is not positive definite (as the prune decides: the statistic then reports it).
bool within_ellipse(const double* d, const double* pa, const double* pb, int m, double c2) {
  const double bound = c2 * (1.0 + 1e-9);
  if (m == 2) {
    const double a = pa[0] + pb[0], b = pa[1] + pb[1], e = pa[2] + pb[2], det = a * e - b * b;
    if (!(a > 0.0) || !(det > 0.0)) return true;
    return d[0] * d[0] * e - 2.0 * d[0] * d[1] * b + d[1] * d[1] * a <= bound * det;
  }
  if (m == 3) {
    const double a = pa[0] + pb[0], b = pa[1] + pb[1], c = pa[2] + pb[2], e = pa[3] + pb[3],
                 f = pa[4] + pb[4], g = pa[5] + pb[5];
    const double A = e * g - f * f, B = c * f - b * g, Cc = b * f - c * e;  // first row of the adjugate
    const double det = a * A + b * B + c * Cc, minor2 = a * e - b * b;
    if (!(a > 0.0) || !(minor2 > 0.0) || !(det > 0.0)) return true;
    const double E = a * g - c * c, F = b * c - a * f;
    const double q = d[0] * d[0] * A + d[1] * d[1] * E + d[2] * d[2] * minor2 +
                     2.0 * (d[0] * d[1] * B + d[0] * d[2] * Cc + d[1] * d[2] * F);
    return q <= bound * det;
  }
  return true;  // (m = 1: the circle is the ellipse, widened as the spreads are)
}

// The per-scan bound: |d_p|² ≤ (s_a + s_b)·c for positions xa, xb and position spreads sa, sb
// (position_spread; the circle, cheap), then d_pᵀ C_pp⁻¹ d_p ≤ c (the ellipse inside it, for the
// position blocks pa, pb). On elongated radar covariances the ellipse holds a small part of the
// circle's pairs.
bool within_points(const double* xa, double sa, const double* pa, const double* xb, double sb,
                   const double* pb, int m, double c2) {
  double d[3] = {}, d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    d[c] = xa[c] - xb[c];
    d2 += d[c] * d[c];
  }
  if (!(d2 <= (sa + sb) * c2)) return false;
  return within_ellipse(d, pa, pb, m, c2);
}

bool within(const AlignedTracks& a, int64_t ca, const AlignedTracks& b, int64_t cb, int m, double c2) {
  const int D = a.dim;
  double pa[kPositionBlock], pb[kPositionBlock];
  position_block(a.cov_at(ca), D, m, pa);
  position_block(b.cov_at(cb), D, m, pb);
  return within_points(a.state_at(ca), position_spread(pa, m), pa, b.state_at(cb), position_spread(pb, m), pb,
                       m, c2);
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

// One sensor's tracks valid at one common time, gathered once for all its pairs of sensors
// (contiguous, so the passes below do not chase each track's cells): track, position (m
// coordinates), position spread s (position_spread) and radius √(2·s·c); their bounding box and
// largest spread.
struct ScanSet {
  std::vector<int32_t> track;
  std::vector<double> pos, spread, radius;
  std::vector<double> block;  // kPositionBlock a track: its position block (position_block)
  std::array<double, 3> lo{}, hi{};
  double max_spread = 0.0;
  std::size_t size() const { return track.size(); }

  void gather(const AlignedTracks& x, std::span<const int32_t> at, int32_t k, double c2) {
    const int D = x.dim, m = D / 2;
    track.assign(at.begin(), at.end());
    pos.resize(at.size() * m);
    block.resize(at.size() * kPositionBlock);
    spread.resize(at.size());
    radius.resize(at.size());
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    max_spread = -std::numeric_limits<double>::infinity();
    // Each track's cells lie apart in memory (a track's span, then the next track's): the state's
    // positions and the packed covariance's position entries (up to its 12 first doubles, two
    // cache lines) of the track kAhead on are asked for before they are read (recorded_10k's
    // candidates stage 298 -> 292 ms, the scale study's 22.5 -> 21.0 ms, one thread).
    constexpr std::size_t kAhead = 8;
    const int position_entries = packed_index(D, m - 1, m - 1) + 1;
    for (std::size_t p = 0; p < at.size(); ++p) {
      if (p + kAhead < at.size()) {
        const int64_t ahead = x.cell_base(at[p + kAhead]) + k;
        __builtin_prefetch(x.state_at(ahead));
        for (int e = 0; e < position_entries; e += 8) __builtin_prefetch(x.cov_at(ahead) + e);
      }
      const int64_t cell = x.cell_base(at[p]) + k;
      const double* xs = x.state_at(cell);
      for (int c = 0; c < m; ++c) {
        pos[p * m + c] = xs[c];
        lo[c] = std::min(lo[c], xs[c]);  // a NaN coordinate (never within) leaves the box as it is
        hi[c] = std::max(hi[c], xs[c]);
      }
      position_block(x.cov_at(cell), D, m, &block[p * kPositionBlock]);
      spread[p] = position_spread(&block[p * kPositionBlock], m);
      radius[p] = std::sqrt(2.0 * spread[p] * c2);
      max_spread = std::max(max_spread, spread[p]);
    }
  }
};

// Scratch of one scan's grid: (grid cell, index into the grid's ScanSet), sorted; and, when the
// cells of the points' bounding box are few (at most kTableCellsPerPoint a point, and 64), the same
// as a table: the points of each cell of the box contiguous in `order`, cell q's at
// [first[q], first[q + 1]). (32: the ball's cells at the median radius, 27 to 125 in 3-D, of about
// one point each in the scale study's boxes; 4 sent its 3-D boxes to the sorted form.)
constexpr double kTableCellsPerPoint = 32.0;
struct GridScratch {
  std::vector<std::pair<Cell, int32_t>> cells;
  std::vector<double> r;
  std::vector<int32_t> first, order, cursor;
};

bool cell_less(const Cell& x, const Cell& y) {
  return x[0] != y[0] ? x[0] < y[0] : (x[1] != y[1] ? x[1] < y[1] : x[2] < y[2]);
}

// A hit of the index: sensor pair slot, track of the first sensor, track of the second, and the
// number of scans at which the pair was within its bound (saturating at 65 535; the slot fits 16
// bits since S ≤ 256 is checked), so a hit takes 12 bytes.
struct Hit {
  int32_t a, b;
  uint16_t slot, count;
  friend bool operator<(const Hit& x, const Hit& y) {
    return x.slot != y.slot ? x.slot < y.slot : (x.a != y.a ? x.a < y.a : x.b < y.b);
  }
  bool same_pair(const Hit& y) const { return slot == y.slot && a == y.a && b == y.b; }
};
static_assert(sizeof(Hit) == 12);

uint16_t saturating_sum(uint16_t x, uint16_t y) {
  return static_cast<uint16_t>(std::min<uint32_t>(uint32_t{x} + y, std::numeric_limits<uint16_t>::max()));
}

// Sorts one scan's hits in Hit's order (slot, a, b): by radix (kernels/core/radix_sort.hpp) on the
// key slot·2^(2w) + a·2^w + b, w the bits of the largest track index (B = 23 bits on the scale
// study's 3 × 1 000 tracks: 2 passes, where std::sort's comparisons of 12-byte hits were a fifth
// of the index's time, docs/performance.md), with `buffer` as its scratch (its contents dropped,
// its growth told to `gauge`); by std::sort below 512 hits, or when w > 24 (the key would not fit
// 64 bits).
void sort_scan_hits(std::vector<Hit>& hits, std::vector<Hit>& buffer, int track_bits,
                    AllocationGauge* gauge) {
  if (hits.size() < 512 || track_bits > 24) {
    std::sort(hits.begin(), hits.end());
    return;
  }
  buffer.clear();  // (so that a reserve copies nothing)
  gauged_reserve(buffer, hits.size(), gauge);
  const int w = track_bits;
  radix_sort_by_key(hits, buffer, [w](const Hit& h) {
    return (uint64_t{h.slot} << (2 * w)) | (static_cast<uint64_t>(h.a) << w) | static_cast<uint64_t>(h.b);
  });
}

// Sorted by pair, each pair once; its count the sum of its copies' counts.
void sort_summing(std::vector<Hit>& hits) {
  std::sort(hits.begin(), hits.end());
  std::size_t w = 0;
  for (std::size_t r = 0; r < hits.size(); ++r) {
    if (w > 0 && hits[w - 1].same_pair(hits[r]))
      hits[w - 1].count = saturating_sum(hits[w - 1].count, hits[r].count);
    else
      hits[w++] = hits[r];
  }
  hits.resize(w);
}

// The union of two sorted, summed lists, counts of a pair in both summed.
void merge_summing(const std::vector<Hit>& x, const std::vector<Hit>& y, std::vector<Hit>& out) {
  auto i = x.begin(), j = y.begin();
  while (i != x.end() && j != y.end()) {
    if (*i < *j) {
      out.push_back(*i++);
    } else if (*j < *i) {
      out.push_back(*j++);
    } else {
      out.push_back(*i++);
      out.back().count = saturating_sum(out.back().count, j++->count);
    }
  }
  out.insert(out.end(), i, x.end());
  out.insert(out.end(), j, y.end());
}

// One pass at one scan: the points qi of `q` (queries) against the points gi of `g` (the grid);
// cell size h, the median radius of gi. Appends (a, b) hits of `slot`. Two forms:
//   two passes (one_pass false): each query is checked against the grid points whose radius is at
//     most its own, within its radius r_q = √(2·s_q·c) (the pass from a, then the pass from b,
//     find each pair once; grid_spread unused);
//   one pass: each query against every grid point, within √((s_q + grid_spread)·c), grid_spread the
//     largest spread of gi, which holds every pair's bound √((s_q + s_g)·c).
template <bool one_pass>
void scan_pass(const ScanSet& q, std::span<const int32_t> qi, const ScanSet& g, std::span<const int32_t> gi,
               int m, double c2, bool q_is_a, double grid_spread, int32_t slot, GridScratch& scratch,
               std::vector<Hit>& out, AllocationGauge* gauge) {
  if (gi.empty() || qi.empty()) return;
  std::vector<std::pair<Cell, int32_t>>& cells = scratch.cells;
  std::vector<double>& r = scratch.r;
  r.clear();
  for (const int32_t p : gi) r.push_back(g.radius[p]);
  std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
  double h = r[r.size() / 2];  // the median radius: most queries touch 3^m cells
  if (!(h > 0.0) || !std::isfinite(h)) h = 1e-9;
  cells.clear();
  for (const int32_t p : gi) cells.emplace_back(cell_of(&g.pos[p * m], m, h), p);
  // The table of the box's cells (row-major, the last axis fastest) when they are few: a row of
  // cells is then one contiguous range, found without a search.
  Cell lo_cell = cells.front().first, hi_cell = lo_cell;
  for (const auto& e : cells)
    for (int d = 0; d < m; ++d)
      lo_cell[d] = std::min(lo_cell[d], e.first[d]), hi_cell[d] = std::max(hi_cell[d], e.first[d]);
  Cell extent{1, 1, 1};
  double box_cells = 1.0;
  for (int d = 0; d < m; ++d) {
    box_cells *= static_cast<double>(hi_cell[d]) - static_cast<double>(lo_cell[d]) + 1.0;
    extent[d] = hi_cell[d] - lo_cell[d] + 1;
  }
  const bool table = box_cells <= kTableCellsPerPoint * static_cast<double>(cells.size()) + 64.0;
  auto table_index = [&](const Cell& c) {
    int64_t index = 0;
    for (int d = 0; d < m; ++d) index = index * extent[d] + (c[d] - lo_cell[d]);
    return index;
  };
  std::vector<int32_t>&first = scratch.first, &order = scratch.order;
  if (table) {
    first.assign(static_cast<std::size_t>(box_cells) + 1, 0);
    for (const auto& e : cells) ++first[table_index(e.first) + 1];
    for (std::size_t k = 1; k < first.size(); ++k) first[k] += first[k - 1];
    order.resize(cells.size());
    std::vector<int32_t>& next = scratch.cursor;
    next.assign(first.begin(), first.end() - 1);
    for (const auto& e : cells)
      order[next[table_index(e.first)]++] = e.second;  // gi ascending: p ascending per cell
  } else {
    std::sort(cells.begin(), cells.end(), [](const auto& x, const auto& y) {
      return cell_less(x.first, y.first) || (x.first == y.first && x.second < y.second);
    });
  }
  const double n_g = static_cast<double>(cells.size()), search_cost = std::max(1.0, std::log2(n_g));
  for (const int32_t i : qi) {
    const double* xq = &q.pos[i * m];
    const double spread_q = q.spread[i];
    double rq = q.radius[i];
    if constexpr (one_pass) rq = std::sqrt((spread_q + grid_spread) * c2);
    const double span_d = std::ceil(rq / h);
    auto consider = [&](int32_t p) __attribute__((always_inline)) {
      // Each pair once: from the side with the larger radius (ties: from a).
      if constexpr (!one_pass)
        if (q_is_a ? g.radius[p] > rq : g.radius[p] >= rq) return;
      const double* xg = &g.pos[p * m];
      const double *bq = &q.block[i * kPositionBlock], *bg = &g.block[p * kPositionBlock];
      if (q_is_a ? within_points(xq, spread_q, bq, xg, g.spread[p], bg, m, c2)
                 : within_points(xg, g.spread[p], bg, xq, spread_q, bq, m, c2))
        gauged_push_back(out,
                         q_is_a ? Hit{q.track[i], g.track[p], static_cast<uint16_t>(slot), 1}
                                : Hit{g.track[p], q.track[i], static_cast<uint16_t>(slot), 1},
                         gauge);
    };
    // The cells within span of the query's cell are read row by row along the last axis (a row is
    // contiguous in the sorted cells): (2·span + 1)^(m−1) binary searches. A query for which these
    // cost more than reading every point (one huge covariance among small ones) reads every point
    // once instead, so its cost is bounded by O(n_g).
    double rows = 1.0;
    for (int d = 1; d < m; ++d) rows *= 2.0 * span_d + 1.0;
    if (!(span_d <= n_g) || !(rows * search_cost <= n_g)) {  // (a NaN radius, from a broken covariance, too)
      for (const auto& e : cells) consider(e.second);
      continue;
    }
    const int64_t span = static_cast<int64_t>(span_d);
    const Cell c = cell_of(xq, m, h);
    if (table) {
      // The cells that meet the query's ball |x − x_q| ≤ r_q, clipped to the box: on the first axes
      // (rows) those whose gap to the query leaves some of the ball, and on each row (the last axis)
      // the chord of the ball that is left, one range of `order` (its start at the row's offset in
      // the table). In cell units u = x/h (the division of cell_of), a cell k holds [k, k + 1); the
      // radius is widened by a relative 10⁻⁹ and 10⁻⁶ of a cell, so a point on a face is not lost
      // to round-off. Against the cube of (2·span + 1)^m cells: 5³ → about 3/5 of them at span 2.
      const double reach = rq / h * (1.0 + 1e-9) + 1e-6;
      const auto ball_span = static_cast<int64_t>(std::ceil(reach));  // (≤ n_g + 1, checked above)
      std::array<double, 3> u{};
      std::array<int64_t, 3> from{0, 0, 0}, to{0, 0, 0};
      bool empty = false;
      for (int d = 0; d < m; ++d) {
        u[d] = xq[d] / h;
        from[d] = std::max(c[d] - ball_span, lo_cell[d]);
        to[d] = std::min(c[d] + ball_span, hi_cell[d]);
        empty = empty || from[d] > to[d] || !std::isfinite(u[d]);  // (a NaN position is never within)
      }
      if (empty) continue;
      const int last = m - 1;
      if (!(std::abs(u[last]) + reach < 4.0e18)) {  // (a chord's floor would not fit int64: every point)
        for (const auto& e : cells) consider(e.second);
        continue;
      }
      auto gap = [&](int d, int64_t k) {  // from u[d] to cell k along axis d, in cell units
        const auto kd = static_cast<double>(k);
        return k > c[d] ? kd - u[d] : k < c[d] ? u[d] - (kd + 1.0) : 0.0;
      };
      auto read_row = [&](int64_t row, double left)
          __attribute__((always_inline)) {  // left: the squared reach the row's axis keeps
        const double chord = std::sqrt(left);
        const int64_t z0 = std::max(from[last], static_cast<int64_t>(std::floor(u[last] - chord)));
        const int64_t z1 = std::min(to[last], static_cast<int64_t>(std::floor(u[last] + chord)));
        if (z0 > z1) return;
        for (int32_t e = first[row + z0 - lo_cell[last]], stop = first[row + z1 - lo_cell[last] + 1];
             e < stop; ++e)
          consider(order[e]);
      };
      const double reach2 = reach * reach;
      if (m == 1) {
        read_row(0, reach2);
      } else {
        for (int64_t x = from[0]; x <= to[0]; ++x) {
          const double gx = gap(0, x), left_x = reach2 - gx * gx;
          if (left_x < 0.0) continue;
          if (m == 2) {
            read_row((x - lo_cell[0]) * extent[1], left_x);
            continue;
          }
          for (int64_t y = from[1]; y <= to[1]; ++y) {
            const double gy = gap(1, y), left = left_x - gy * gy;
            if (left >= 0.0) read_row(((x - lo_cell[0]) * extent[1] + (y - lo_cell[1])) * extent[2], left);
          }
        }
      }
      continue;
    }
    const int last = m - 1;  // the axis of a row
    const int64_t sx = m >= 2 ? span : 0, sy = m == 3 ? span : 0;
    for (int64_t dx = -sx; dx <= sx; ++dx)
      for (int64_t dy = -sy; dy <= sy; ++dy) {
        Cell key{c[0] + dx, c[1] + dy, c[2]};
        key[last] = c[last] - span;
        const int64_t row_end = c[last] + span;
        auto it = std::lower_bound(cells.begin(), cells.end(), key,
                                   [](const auto& e, const Cell& k) { return cell_less(e.first, k); });
        for (; it != cells.end(); ++it) {
          bool same_row = it->first[last] <= row_end;
          for (int d = 0; d < last; ++d) same_row = same_row && it->first[d] == key[d];
          if (!same_row) break;
          consider(it->second);
        }
      }
  }
}

// The points of `x` that can be within the bound of some point of `other` at this scan: inside
// other's bounding box widened by R = √((max s_x + max s_other)·c) on every axis (a pair within
// its bound has |d_c| ≤ |d_p| ≤ R per axis; the factor 1 + 10⁻⁹ covers the round-off of both
// tests, so nothing within is dropped).
void points_near(const ScanSet& x, const ScanSet& other, double reach, int m, std::vector<int32_t>& out) {
  out.clear();
  for (std::size_t p = 0; p < x.size(); ++p) {
    bool in = true;
    for (int c = 0; c < m && in; ++c) {
      const double v = x.pos[p * m + c];
      in = v >= other.lo[c] - reach && v <= other.hi[c] + reach;
    }
    if (in) out.push_back(static_cast<int32_t>(p));
  }
}

// The largest and the mean spread of the points `at` of x (0 and 0 for none; a NaN spread makes the
// largest NaN, so that the two passes are used).
std::pair<double, double> spread_range(const ScanSet& x, std::span<const int32_t> at) {
  double most = 0.0, sum = 0.0;
  for (const int32_t p : at) {
    most = std::isnan(most) || std::isnan(x.spread[p]) ? std::numeric_limits<double>::quiet_NaN()
                                                       : std::max(most, x.spread[p]);
    sum += x.spread[p];
  }
  return {most, at.empty() ? 0.0 : sum / static_cast<double>(at.size())};
}

// The candidate pairs of the sensor pairs (s, t), s < t, of one scan k.
struct ScanScratch {
  std::vector<ScanSet> sets;
  std::vector<int32_t> near_s, near_t;
  GridScratch grid;
};

void scan_all_pairs(std::span<const AlignedTracks* const> x, std::span<const ValidByTime> valid, int32_t k,
                    double c2, ScanScratch& scratch, std::vector<Hit>& out, AllocationGauge* gauge) {
  const auto S = static_cast<int32_t>(x.size());
  const int m = x[0]->dim / 2;
  scratch.sets.resize(S);
  for (int32_t s = 0; s < S; ++s) scratch.sets[s].gather(*x[s], valid[s].at(k), k, c2);
  for (int32_t s = 0; s < S; ++s)
    for (int32_t t = s + 1; t < S; ++t) {
      const ScanSet &a = scratch.sets[s], &b = scratch.sets[t];
      if (a.size() == 0 || b.size() == 0) continue;
      const double reach = std::sqrt((a.max_spread + b.max_spread) * c2) * (1.0 + 1e-9);
      bool apart = false;  // the boxes farther apart than the reach on some axis
      for (int c = 0; c < m; ++c) apart = apart || a.lo[c] > b.hi[c] + reach || b.lo[c] > a.hi[c] + reach;
      if (apart) continue;
      points_near(a, b, reach, m, scratch.near_s);
      points_near(b, a, reach, m, scratch.near_t);
      const int32_t slot = s * S + t;
      // One pass when one side's spreads are even (its largest at most twice the other side's
      // mean; of two such sides, the grid is the one whose largest spread times its mean is the
      // smaller): the ball √((s_q + max s_g)·c) is then hardly wider than the two passes' √(2·s_q·c),
      // and each track is a query once instead of twice (the scale study's tracks, the same σ on
      // every track: the largest 1.6 times the median). Otherwise (radars: spreads over decades with
      // range) the two passes.
      const auto [most_a, mean_a] = spread_range(a, scratch.near_s);
      const auto [most_b, mean_b] = spread_range(b, scratch.near_t);
      if (most_b <= 2.0 * mean_a && most_b * mean_b <= most_a * mean_a) {
        scan_pass<true>(a, scratch.near_s, b, scratch.near_t, m, c2, true, most_b, slot, scratch.grid, out,
                        gauge);
      } else if (most_a <= 2.0 * mean_b) {
        scan_pass<true>(b, scratch.near_t, a, scratch.near_s, m, c2, false, most_a, slot, scratch.grid, out,
                        gauge);
      } else {
        scan_pass<false>(a, scratch.near_s, b, scratch.near_t, m, c2, true, 0.0, slot, scratch.grid, out,
                         gauge);
        scan_pass<false>(b, scratch.near_t, a, scratch.near_s, m, c2, false, 0.0, slot, scratch.grid, out,
                         gauge);
      }
    }
}

}  // namespace

std::vector<CandidatePairs> scan_candidate_pairs(std::span<const AlignedTracks* const> sensors, double cap,
                                                 double radius_scale, AllocationGauge* gauge,
                                                 std::span<const int32_t> least_hits,
                                                 std::vector<std::size_t>* found) {
  const auto S = static_cast<int32_t>(sensors.size());
  require(S <= 256, "scan_candidate_pairs",
          "at most 256 sensors (a sensor pair is held in 16 bits), got " + std::to_string(S));
  std::vector<CandidatePairs> out(static_cast<std::size_t>(S) * S);
  for (int32_t s = 0; s < S; ++s)
    for (int32_t t = s + 1; t < S; ++t) {
      check_inputs(*sensors[s], *sensors[t], cap, radius_scale);
      out[static_cast<std::size_t>(s) * S + t].n_a = sensors[s]->n_tracks();
      out[static_cast<std::size_t>(s) * S + t].n_b = sensors[t]->n_tracks();
    }
  if (found) found->assign(out.size(), 0);
  if (S < 2) return out;
  const int32_t K = sensors[0]->n_times;
  const double c2 = cap * radius_scale * radius_scale;
  // Lossless: (s_a + s_b)·c ≤ 2·max(s_a, s_b)·c, so a pair within its bound is within the larger
  // of the two radii √(2·s·c); each pair is searched from the track with the larger one (two
  // passes: a over b's grid, b over a's grid), so one wide track does not coarsen the grid; or,
  // for tracks of even spreads, in one pass (scan_all_pairs).
  // Each scan's tracks come from the spans (valid_by_time) and are gathered once for all pairs of
  // sensors; a pair of sensors meets only where their boxes do (points_near), so sensors far apart
  // cost one box test per scan. Scans in blocks of consecutive times (a pair found at one is
  // mostly found at the next), each block's hits deduplicated before they are kept.
  // The index of valid tracks by time (offsets and the counting pass's cursors, 2·(K + 1) int64,
  // and at most one int32 per cell of each span), counted before it is built.
  double valid_bytes = 0.0;
  for (int32_t s = 0; s < S; ++s) {
    valid_bytes += 16.0 * (static_cast<double>(K) + 1.0);
    for (int32_t i = 0; i < sensors[s]->n_tracks(); ++i) {
      const AlignedTracks::Span sp = sensors[s]->span(i);
      valid_bytes += 4.0 * std::max(0, sp.end - sp.begin);
    }
  }
  gauge_add(gauge, valid_bytes);
  std::vector<ValidByTime> valid(S);
  parallel_for_range(static_cast<std::size_t>(S), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t s = lo; s < hi; ++s) valid[s] = valid_by_time(*sensors[s]);
  });
  // Each thread's scratch of one scan (its sensors' valid tracks gathered: track, m coordinates,
  // spread, radius, position block; the points near the other sensor; the grid's cells and radii),
  // at most the largest number of tracks valid at one time, counted before the scans for every
  // thread.
  double scratch_bytes = 0.0;
  std::size_t widest = 0;
  for (int32_t s = 0; s < S; ++s) {
    std::size_t most = 0;
    for (int32_t k = 0; k < K; ++k) most = std::max(most, valid[s].at(k).size());
    scratch_bytes +=
        static_cast<double>(most) * (4.0 + 8.0 * (sensors[s]->dim / 2) + 16.0 + 8.0 * kPositionBlock);
    widest = std::max(widest, most);
  }
  // (and the grid's table: at most kTableCellsPerPoint cells a point and 64, an offset and a cursor
  // each, and its order of the points)
  scratch_bytes += static_cast<double>(widest) *
                       (2 * 4.0 + sizeof(std::pair<Cell, int32_t>) + 8.0 + 8.0 * kTableCellsPerPoint + 4.0) +
                   520.0;
  scratch_bytes *= static_cast<double>(std::max(1, tbb::this_task_arena::max_concurrency()));
  gauge_add(gauge, scratch_bytes);
  int32_t most_tracks = 1;  // the key of sort_scan_hits: the bits of the largest track index
  for (int32_t s = 0; s < S; ++s) most_tracks = std::max(most_tracks, sensors[s]->n_tracks());
  const int track_bits = std::bit_width(static_cast<uint32_t>(most_tracks - 1));
  // Blocks of at most 8 scans, and at least as many blocks as threads while there are scans enough
  // (a file of 11 common times in blocks of 8 and 3 left one thread idle for most of the index).
  // The blocking does not change the output: each pair's count is summed over the blocks.
  const int32_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
  const int32_t least_blocks = std::max({1, (K + 7) / 8, std::min(K, threads)});
  const int32_t block = std::max(1, (K + least_blocks - 1) / least_blocks);  // scans a block
  const std::size_t blocks = (static_cast<std::size_t>(K) + block - 1) / block;
  std::vector<std::vector<Hit>> per_block(blocks);
  parallel_for_range(blocks, 1, [&](std::size_t lo, std::size_t hi) {
    ScanScratch scratch;
    // Each scan's hits are merged into the block's sorted set at once (a pair found at one scan is
    // mostly found at the next: kept until the block ends, the copies made a block of recorded_30k
    // ask for 768 MiB where its pairs take ~100 MiB).
    std::vector<Hit> scan, merged;
    for (std::size_t bl = lo; bl < hi; ++bl) {
      std::vector<Hit>& kept = per_block[bl];
      const auto k0 = static_cast<int32_t>(bl) * block;
      for (int32_t k = k0; k < std::min(K, k0 + block); ++k) {
        scan.clear();
        scan_all_pairs(sensors, valid, k, c2, scratch, scan, gauge);
        // Each pair once per scan (count 1): a count is a number of scans.
        sort_scan_hits(scan, merged, track_bits, gauge);  // (merged is free until the merge)
        scan.erase(
            std::unique(scan.begin(), scan.end(), [](const Hit& x, const Hit& y) { return x.same_pair(y); }),
            scan.end());
        gauged_reserve(merged, kept.size() + scan.size(), gauge);
        merged.clear();
        merge_summing(kept, scan, merged);
        kept.swap(merged);
      }
    }
    gauge_release(gauge, static_cast<double>((scan.capacity() + merged.capacity()) * sizeof(Hit)));
  });
  gauge_release(gauge, scratch_bytes);  // freed with each thread's scratch
  std::vector<Hit> all;
  std::size_t total = 0;
  for (const auto& v : per_block) total += v.size();
  gauge_add(gauge, static_cast<double>(total * sizeof(Hit)));
  all.reserve(total);
  for (auto& v : per_block) {
    all.insert(all.end(), v.begin(), v.end());
    const double freed = static_cast<double>(v.capacity() * sizeof(Hit));
    std::vector<Hit>().swap(v);
    gauge_release(gauge, freed);
  }
  std::vector<ValidByTime>().swap(valid);
  gauge_release(gauge, valid_bytes);
  sort_summing(all);  // by slot, then (a, b): each slot's pairs sorted, with their scans within
  // The count filter (least_hits): a pair within its bound at fewer scans than the least for a
  // lower bound of its common valid scans is dropped; n ≥ |span_a ∩ span_b| − gaps_a − gaps_b, the
  // gaps being the invalid cells inside each track's span.
  std::vector<std::vector<int32_t>> gaps(least_hits.empty() ? 0 : S);
  for (std::size_t s = 0; s < gaps.size(); ++s) {
    const AlignedTracks& x = *sensors[s];
    gaps[s].assign(x.n_tracks(), 0);
    for (int32_t i = 0; i < x.n_tracks(); ++i) {
      const AlignedTracks::Span sp = x.span(i);
      for (int32_t k = sp.begin; k < sp.end; ++k) gaps[s][i] += !x.valid[x.cell_base(i) + k];
    }
  }
  auto dropped = [&](const Hit& h) {
    const int32_t s = h.slot / S, t = h.slot % S;
    const int64_t n = static_cast<int64_t>(common_span(sensors[s]->span(h.a), sensors[t]->span(h.b)).size()) -
                      gaps[s][h.a] - gaps[t][h.b];
    const auto at =
        static_cast<std::size_t>(std::clamp<int64_t>(n, 0, static_cast<int64_t>(least_hits.size()) - 1));
    return int32_t{h.count} < std::min<int32_t>(least_hits[at], std::numeric_limits<uint16_t>::max());
  };
  if (found)
    for (const Hit& h : all) ++(*found)[h.slot];
  if (!least_hits.empty()) std::erase_if(all, dropped);  // in place: no second buffer
  // Each slot's pairs counted, then laid out (exactly their size: 8 bytes a pair) beside the hits.
  std::vector<std::size_t> per_slot(out.size(), 0);
  for (const Hit& h : all) ++per_slot[h.slot];
  gauge_add(gauge, static_cast<double>(all.size() * 2 * sizeof(int32_t)));
  for (std::size_t slot = 0; slot < out.size(); ++slot) {
    out[slot].a.reserve(per_slot[slot]);
    out[slot].b.reserve(per_slot[slot]);
  }
  for (const Hit& h : all) {
    out[h.slot].a.push_back(h.a);
    out[h.slot].b.push_back(h.b);
  }
  const double hits = static_cast<double>(all.capacity() * sizeof(Hit));
  std::vector<Hit>().swap(all);
  gauge_release(gauge, hits);
  return out;
}

CandidatePairs scan_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                    double radius_scale) {
  check_inputs(a, b, cap, radius_scale);
  const AlignedTracks* both[2] = {&a, &b};
  return std::move(scan_candidate_pairs(both, cap, radius_scale)[1]);
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

}  // namespace trackassoc
