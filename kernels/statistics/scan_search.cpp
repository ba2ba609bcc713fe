// One common time of the per-scan candidate index; see kernels/statistics/scan_search.hpp.
#include "kernels/statistics/scan_search.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "kernels/statistics/scan_bound.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

namespace {

using Cell = GridCell;
constexpr auto cell_of = grid_cell_of;

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

// The grid's table is kept while the cells of the points' bounding box are at most
// kTableCellsPerPoint a point (and 64). 32: the ball's cells at the median radius, 27 to 125 in 3-D,
// of about one point each in the scale study's boxes; 4 sent its 3-D boxes to the sorted form.
constexpr double kTableCellsPerPoint = 32.0;

// A query copies the first kRowCopy points of each row it reads into a buffer of kFound points
// (ScanGrid::visit_table).
constexpr int32_t kRowCopy = 4, kFound = 128;

// Sparse points get cells wider than the median radius, holding about kOccupancy points each on
// average over their box, at most kMostWidening times wider (ScanGrid). Measured on the scale
// study's index (docs/performance.md "Session 36"): 0.3 and 0.5 alike, 0.15 and 0.8 slower.
constexpr double kOccupancy = 0.3, kMostWidening = 2.0;

// The memory a ScanGrid keeps between scans.
struct GridScratch {
  std::vector<std::pair<Cell, int32_t>> cells;
  std::vector<double> r;
  std::vector<int32_t> first, order;
  std::vector<int64_t> index;  // each point's cell in the table
};

bool cell_less(const Cell& x, const Cell& y) {
  return x[0] != y[0] ? x[0] < y[0] : (x[1] != y[1] ? x[1] < y[1] : x[2] < y[2]);
}

// A uniform grid over the points gi of g at one scan, of cell size h the median radius of gi (most
// balls then meet 3^m cells), wider for sparse points (kOccupancy): a table of the cells of their
// bounding box (row-major, the last axis fastest, the points of cell q at order[first[q] ..
// first[q + 1])) when it has at most kTableCellsPerPoint cells a point and 64; else the (cell,
// point) pairs sorted by cell, a row of cells found by binary search.
class ScanGrid {
 public:
  ScanGrid(const ScanSet& g, std::span<const int32_t> gi, int m, GridScratch& s)
      : m_(m), cells_(s.cells), first_(s.first), order_(s.order) {
    s.r.clear();
    for (const int32_t p : gi) s.r.push_back(g.radius[p]);
    std::nth_element(s.r.begin(), s.r.begin() + s.r.size() / 2, s.r.end());
    h_ = s.r[s.r.size() / 2];
    if (!(h_ > 0.0) || !std::isfinite(h_)) h_ = 1e-9;
    // Sparse points (the scale study's: a ball holds ~4 points, and 67 % of the rows it read were
    // empty): the cells widened to hold kOccupancy points each on average over the points' box (at
    // most kMostWidening times wider), so that a ball's rows are not mostly empty reads. In the
    // table form, kept only when the points' own cells then share at most 2·kOccupancy others a
    // point on average: points clustered in a wide box keep the median radius. The sorted form keeps
    // the widening unchecked (checked too, from its runs of equal cells, widearea_small's candidates
    // took 1.5 % longer on 1 and 2 threads for its 2 grids rebuilt; docs/performance.md "Session 37").
    const double h0 = h_, per_cell = points_per_cell(g, gi);
    const bool widened = per_cell < kOccupancy;
    if (widened) h_ *= std::min(kMostWidening, std::pow(kOccupancy / per_cell, 1.0 / m));
    place(g, gi, s);
    if (!widened || !table_) return;
    double shared = 0.0;  // Σ over the points of the others in its cell
    for (const int64_t q : s.index) shared += static_cast<double>(s.first[q + 1] - s.first[q] - 1);
    if (shared <= 2.0 * kOccupancy * n_) return;
    h_ = h0;
    place(g, gi, s);
  }

  // Calls visit(p) for every grid point p that can lie within `radius` of the position x (and
  // others): with the table, those of the cells the ball meets; sorted, those of the cube of cells
  // within ⌈radius/h⌉ of x's. Every point, once, when the rows of cells would cost more than
  // reading them all (one huge covariance among small ones: the cost is bounded by O(points)) or
  // the ball is not finite (a NaN radius, from a broken covariance).
  template <class Visit>
  void visit_ball(const double* x, double radius, Visit&& visit) const {
    const double span = std::ceil(radius / h_);
    double rows = 1.0;
    for (int d = 1; d < m_; ++d) rows *= 2.0 * span + 1.0;
    if (!(span <= n_) || !(rows * search_cost_ <= n_)) return visit_every_point(visit);
    const Cell c = cell_of(x, m_, h_);
    if (table_) return visit_table(x, radius, c, visit);
    visit_sorted(c, static_cast<int64_t>(span), visit);
  }

 private:
  // The points gi of g a cell of size h_ holds on average over their bounding box (+inf when the
  // box is flat on some axis; NaN coordinates left out).
  double points_per_cell(const ScanSet& g, std::span<const int32_t> gi) const {
    std::array<double, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (const int32_t p : gi)
      for (int d = 0; d < m_; ++d) {
        lo[d] = std::min(lo[d], g.pos[p * m_ + d]);
        hi[d] = std::max(hi[d], g.pos[p * m_ + d]);
      }
    double per_cell = static_cast<double>(gi.size());
    for (int d = 0; d < m_; ++d) per_cell *= h_ / (hi[d] - lo[d]);
    return per_cell;
  }

  // The cells of the points gi of g at cell size h_: the table or the sorted form.
  void place(const ScanSet& g, std::span<const int32_t> gi, GridScratch& s) {
    const int m = m_;
    s.cells.clear();
    for (const int32_t p : gi) s.cells.emplace_back(cell_of(&g.pos[p * m], m, h_), p);
    lo_ = hi_ = s.cells.front().first;
    for (const auto& e : s.cells)
      for (int d = 0; d < m; ++d)
        lo_[d] = std::min(lo_[d], e.first[d]), hi_[d] = std::max(hi_[d], e.first[d]);
    double box_cells = 1.0;
    for (int d = 0; d < m; ++d) {
      box_cells *= static_cast<double>(hi_[d]) - static_cast<double>(lo_[d]) + 1.0;
      extent_[d] = hi_[d] - lo_[d] + 1;
    }
    n_ = static_cast<double>(s.cells.size());
    search_cost_ = std::max(1.0, std::log2(n_));
    table_ = box_cells <= kTableCellsPerPoint * n_ + 64.0;
    if (table_) {
      // Counted two cells on (first[q + 2]), summed, then each point placed at first[q + 1], which
      // it advances: first[q] ends as cell q's first point (the counting sort without a cursor).
      s.first.assign(static_cast<std::size_t>(box_cells) + 2, 0);
      s.index.clear();
      for (const auto& e : s.cells) {
        s.index.push_back(table_index(e.first));
        ++s.first[s.index.back() + 2];
      }
      for (std::size_t k = 1; k < s.first.size(); ++k) s.first[k] += s.first[k - 1];
      s.order.resize(s.cells.size() + kRowCopy);  // (padded: a row is copied kRowCopy entries at once)
      for (std::size_t e = 0; e < s.cells.size(); ++e)
        s.order[s.first[s.index[e] + 1]++] = s.cells[e].second;  // gi ascending: p ascending per cell
    } else {
      std::sort(s.cells.begin(), s.cells.end(), [](const auto& x, const auto& y) {
        return cell_less(x.first, y.first) || (x.first == y.first && x.second < y.second);
      });
    }
  }

  int64_t table_index(const Cell& c) const {
    int64_t index = 0;
    for (int d = 0; d < m_; ++d) index = index * extent_[d] + (c[d] - lo_[d]);
    return index;
  }

  template <class Visit>
  void visit_every_point(Visit& visit) const {
    for (const auto& e : cells_) visit(e.second);
  }

  // The cells that meet the ball |y − x| ≤ radius, clipped to the box: on the first axes (rows)
  // those whose gap to x leaves some of the ball, and on each row (the last axis) the chord of the
  // ball that is left, one range of `order`. In cell units u = x/h (the division of cell_of), a
  // cell k holds [k, k + 1); the radius is widened by a relative 10⁻⁹ and 10⁻⁶ of a cell, so a
  // point on a face is not lost to round-off. Against the cube of (2·span + 1)^m cells: 5³ → about
  // 3/5 of them at span 2.
  template <class Visit>
  void visit_table(const double* x, double radius, const Cell& c, Visit& visit) const {
    const int last = m_ - 1;
    const double reach = radius / h_ * (1.0 + 1e-9) + 1e-6;
    const auto ball_span = static_cast<int64_t>(std::ceil(reach));  // (≤ points + 1: visit_ball)
    std::array<double, 3> u{};
    std::array<int64_t, 3> from{0, 0, 0}, to{0, 0, 0};
    for (int d = 0; d < m_; ++d) {
      u[d] = x[d] / h_;
      from[d] = std::max(c[d] - ball_span, lo_[d]);
      to[d] = std::min(c[d] + ball_span, hi_[d]);
      if (from[d] > to[d] || !std::isfinite(u[d])) return;  // (a NaN position is never within)
    }
    if (!(std::abs(u[last]) + reach < 4.0e18))
      return visit_every_point(visit);  // (a chord's floor
                                        // would not fit int64)
    auto gap = [&](int d, int64_t k) {  // from u[d] to cell k along axis d, in cell units
      const auto kd = static_cast<double>(k);
      return k > c[d] ? kd - u[d] : k < c[d] ? u[d] - (kd + 1.0) : 0.0;
    };
    // The points of the rows the ball meets are gathered into `found`, then visited in one loop:
    // most rows are empty (the scale study's: 67 %), and a branch on each row's size was taken or not
    // at random. A row's range is read whether empty or not (`left` < 0: the ball misses it, an
    // empty range), its first kRowCopy entries copied at once and the count advanced by its size; a
    // row of more points is visited directly.
    int32_t found[kFound];
    int n_found = 0;
    auto flush = [&] {
      for (int f = 0; f < n_found; ++f) visit(found[f]);
      n_found = 0;
    };
    // `line`: the row's index among the rows; `left`: the squared reach the row's axis keeps.
    auto read_row = [&](int64_t line, double left) __attribute__((always_inline)) {
      const double chord = std::sqrt(std::max(left, 0.0));
      const int64_t z0 =
          std::clamp(static_cast<int64_t>(std::floor(u[last] - chord)), from[last], to[last] + 1);
      int64_t z1 = std::clamp(static_cast<int64_t>(std::floor(u[last] + chord)) + 1, z0, to[last] + 1);
      z1 = left < 0.0 ? z0 : z1;
      const int64_t row = line * extent_[last] - lo_[last];
      const int32_t begin = first_[row + z0], count = first_[row + z1] - begin;
      if (count > kRowCopy) [[unlikely]] {
        for (int32_t e = begin; e < begin + count; ++e) visit(order_[e]);
        return;
      }
      if (n_found + kRowCopy > kFound) [[unlikely]]
        flush();
      std::copy_n(&order_[begin], kRowCopy, &found[n_found]);
      n_found += count;
    };
    const double reach2 = reach * reach;
    if (m_ == 1) {
      read_row(0, reach2);
      return flush();
    }
    for (int64_t i = from[0]; i <= to[0]; ++i) {
      const double gx = gap(0, i), left_x = reach2 - gx * gx;
      if (left_x < 0.0) continue;
      if (m_ == 2) {
        read_row(i - lo_[0], left_x);
        continue;
      }
      for (int64_t j = from[1]; j <= to[1]; ++j) {
        const double gy = gap(1, j);
        read_row((i - lo_[0]) * extent_[1] + (j - lo_[1]), left_x - gy * gy);
      }
    }
    flush();
  }

  // The cells within `span` of the cell c, row by row along the last axis (a row is contiguous in
  // the sorted cells): (2·span + 1)^(m−1) binary searches.
  template <class Visit>
  void visit_sorted(const Cell& c, int64_t span, Visit& visit) const {
    const int last = m_ - 1;
    const int64_t sx = m_ >= 2 ? span : 0, sy = m_ == 3 ? span : 0;
    for (int64_t dx = -sx; dx <= sx; ++dx)
      for (int64_t dy = -sy; dy <= sy; ++dy) {
        Cell key{c[0] + dx, c[1] + dy, c[2]};
        key[last] = c[last] - span;
        const int64_t row_end = c[last] + span;
        auto it = std::lower_bound(cells_.begin(), cells_.end(), key,
                                   [](const auto& e, const Cell& k) { return cell_less(e.first, k); });
        for (; it != cells_.end(); ++it) {
          bool same_row = it->first[last] <= row_end;
          for (int d = 0; d < last; ++d) same_row = same_row && it->first[d] == key[d];
          if (!same_row) break;
          visit(it->second);
        }
      }
  }

  int m_;
  double h_ = 1e-9, n_ = 0.0, search_cost_ = 1.0;
  bool table_ = false;
  Cell lo_{0, 0, 0}, hi_{0, 0, 0}, extent_{1, 1, 1};
  const std::vector<std::pair<Cell, int32_t>>& cells_;
  const std::vector<int32_t>&first_, &order_;
};

// One pass at one scan: the points qi of `q` (queries) against the points gi of `g` (the grid).
// Appends (a, b) hits of `slot`. Two forms:
//   two passes (one_pass false): each query is checked against the grid points whose radius is at
//     most its own, within its radius r_q = √(2·s_q·c) (the pass from a, then the pass from b,
//     find each pair once: (s_a + s_b)·c ≤ 2·max(s_a, s_b)·c; grid_spread unused);
//   one pass: each query against every grid point, within √((s_q + grid_spread)·c), grid_spread the
//     largest spread of gi, which holds every pair's bound √((s_q + s_g)·c).
template <bool one_pass>
void scan_pass(const ScanSet& q, std::span<const int32_t> qi, const ScanSet& g, std::span<const int32_t> gi,
               int m, double c2, bool q_is_a, double grid_spread, int32_t slot, GridScratch& scratch,
               std::vector<ScanHit>& out, AllocationGauge* gauge) {
  if (gi.empty() || qi.empty()) return;
  const ScanGrid grid(g, gi, m, scratch);
  for (const int32_t i : qi) {
    const double* xq = &q.pos[i * m];
    const double spread_q = q.spread[i];
    const double rq = one_pass ? std::sqrt((spread_q + grid_spread) * c2) : q.radius[i];
    grid.visit_ball(
        xq, rq, [&](int32_t p) __attribute__((always_inline)) {
          // Each pair once: from the side with the larger radius (ties, and a NaN radius: from a; the
          // two conditions are each other's negation, so a pair is found at most once a scan).
          if constexpr (!one_pass)
            if (q_is_a ? g.radius[p] > rq : !(g.radius[p] < rq)) return;
          const double* xg = &g.pos[p * m];
          const double *bq = &q.block[i * kPositionBlock], *bg = &g.block[p * kPositionBlock];
          if (q_is_a ? within_points(xq, spread_q, bq, xg, g.spread[p], bg, m, c2)
                     : within_points(xg, g.spread[p], bg, xq, spread_q, bq, m, c2))
            gauged_push_back(out,
                             q_is_a ? ScanHit{q.track[i], g.track[p], static_cast<uint16_t>(slot), 1}
                                    : ScanHit{g.track[p], q.track[i], static_cast<uint16_t>(slot), 1},
                             gauge);
        });
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

// Every pair of the points ai of a and bi of b within its bound, appended as hits of `slot`. One
// pass when one side's spreads are even (its largest at most twice the other side's mean; of two
// such sides, the grid is the one whose largest spread times its mean is the smaller): the ball
// √((s_q + max s_g)·c) is then hardly wider than the two passes' √(2·s_q·c), and each track is a
// query once instead of twice (the scale study's tracks, the same σ on every track: the largest 1.6
// times the median). Otherwise (radars: spreads over decades with range) the two passes.
void search_pairs(const ScanSet& a, std::span<const int32_t> ai, const ScanSet& b,
                  std::span<const int32_t> bi, int m, double c2, int32_t slot, GridScratch& grid,
                  std::vector<ScanHit>& out, AllocationGauge* gauge) {
  if (ai.empty() || bi.empty()) return;
  const auto [most_a, mean_a] = spread_range(a, ai);
  const auto [most_b, mean_b] = spread_range(b, bi);
  if (most_b <= 2.0 * mean_a && most_b * mean_b <= most_a * mean_a) {
    scan_pass<true>(a, ai, b, bi, m, c2, true, most_b, slot, grid, out, gauge);
  } else if (most_a <= 2.0 * mean_b) {
    scan_pass<true>(b, bi, a, ai, m, c2, false, most_a, slot, grid, out, gauge);
  } else {
    scan_pass<false>(a, ai, b, bi, m, c2, true, 0.0, slot, grid, out, gauge);
    scan_pass<false>(b, bi, a, ai, m, c2, false, 0.0, slot, grid, out, gauge);
  }
}

// The points `at` of a sensor's set split into those whose track is at its edge (is_edge, by point)
// and, when `inner` is given, the others.
void split_at_edge(std::span<const int32_t> at, const std::vector<uint8_t>& is_edge,
                   std::vector<int32_t>& edge, std::vector<int32_t>* inner) {
  edge.clear();
  if (inner) inner->clear();
  for (const int32_t p : at)
    if (is_edge[p])
      edge.push_back(p);
    else if (inner)
      inner->push_back(p);
}

}  // namespace

struct ScanSearch::Scratch {
  std::vector<ScanSet> sets;
  std::vector<int32_t> near_s, near_t, edge_s, inner_s, edge_t;
  std::vector<std::vector<uint8_t>> edge;  // a partial scan: per sensor, per gathered point
  GridScratch grid;
};

ScanSearch::ScanSearch() : scratch_(std::make_unique<Scratch>()) {}
ScanSearch::~ScanSearch() = default;

void ScanSearch::scan(std::span<const AlignedTracks* const> x, std::span<const ValidByTime> valid, int32_t k,
                      double c2, std::vector<ScanHit>& out, AllocationGauge* gauge,
                      const PartialScan* partial) {
  Scratch& scratch = *scratch_;
  const auto S = static_cast<int32_t>(x.size());
  const int m = x[0]->dim / 2;
  if (partial) {  // each valid track at its edge or not (in the gather's order); none: nothing to search
    scratch.edge.resize(S);
    bool any = false;
    for (int32_t s = 0; s < S; ++s) {
      const std::span<const int32_t> at = valid[s].at(k);
      scratch.edge[s].resize(at.size());
      for (std::size_t p = 0; p < at.size(); ++p) {
        scratch.edge[s][p] = partial->edge(*x[s], s, at[p], k);
        any = any || scratch.edge[s][p];
      }
    }
    if (!any) return;
  }
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
      if (!partial) {
        search_pairs(a, scratch.near_s, b, scratch.near_t, m, c2, slot, scratch.grid, out, gauge);
        continue;
      }
      // The pairs with an edge track: (edge of s) × (all of t), then (inner of s) × (edge of t).
      split_at_edge(scratch.near_s, scratch.edge[s], scratch.edge_s, &scratch.inner_s);
      split_at_edge(scratch.near_t, scratch.edge[t], scratch.edge_t, nullptr);
      search_pairs(a, scratch.edge_s, b, scratch.near_t, m, c2, slot, scratch.grid, out, gauge);
      search_pairs(a, scratch.inner_s, b, scratch.edge_t, m, c2, slot, scratch.grid, out, gauge);
    }
}

double ScanSearch::scratch_bytes(std::span<const AlignedTracks* const> sensors,
                                 std::span<const ValidByTime> valid) {
  // Each sensor's valid tracks gathered (track, m coordinates, spread, radius, position block) at
  // most the largest number of tracks valid at one time; the points near the other sensor, the
  // grid's cells and radii, and its table (at most kTableCellsPerPoint cells a point and 64, an
  // offset each; each point's cell in it, and its order of the points, padded by kRowCopy); a
  // partial scan's edge flags (a byte a track) and its edge and inner lists.
  double bytes = 0.0;
  std::size_t widest = 0;
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    std::size_t most = 0;
    for (int32_t k = 0; k < sensors[s]->n_times; ++k) most = std::max(most, valid[s].at(k).size());
    bytes += static_cast<double>(most) * (5.0 + 8.0 * (sensors[s]->dim / 2) + 16.0 + 8.0 * kPositionBlock);
    widest = std::max(widest, most);
  }
  return bytes +
         static_cast<double>(widest) *
             (5 * 4.0 + sizeof(std::pair<Cell, int32_t>) + 8.0 + 4.0 * kTableCellsPerPoint + 8.0 + 4.0) +
         520.0 + 4.0 * kRowCopy;
}

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

}  // namespace trackassoc
