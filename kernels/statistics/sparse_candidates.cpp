// Sparse gated candidates: the grid index and λ on candidate pairs. See the header for the bound.
#include "kernels/statistics/sparse_candidates.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

void CandidateOptions::validate() const {
  require(gate_probability > 0.0 && gate_probability < 1.0, "CandidateOptions.gate_probability",
          "the sparse form needs a chi-square gate in (0, 1) (1 would make every pair a candidate), got " +
              std::to_string(gate_probability));
  require(std::isfinite(radius_scale) && radius_scale >= 1.0, "CandidateOptions.radius_scale",
          "must be finite and >= 1, got " + std::to_string(radius_scale));
}

TrackIndexKeys track_index_keys(const AlignedTracks& x) {
  const int D = x.dim, m = D / 2;
  const int32_t n = x.n_tracks();
  TrackIndexKeys keys;
  keys.spatial_dim = m;
  keys.mean_position.assign(static_cast<std::size_t>(n) * m, 0.0);
  keys.max_position_variance.assign(n, 0.0);
  keys.valid_times.assign(n, 0);
  keys.trajectory_radius.assign(n, 0.0);
  // Largest eigenvalue of the m×m position block: closed form for m ≤ 3 (Eigen computeDirect).
  auto max_eigenvalue = [&](const double* packed) {
    if (m == 1) return packed[0];
    if (m == 2) {
      Eigen::Matrix2d A;
      A << packed[packed_index(D, 0, 0)], packed[packed_index(D, 0, 1)], packed[packed_index(D, 0, 1)],
          packed[packed_index(D, 1, 1)];
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es;
      es.computeDirect(A, Eigen::EigenvaluesOnly);
      return es.eigenvalues().maxCoeff();
    }
    Eigen::Matrix3d A;
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) A(r, c) = A(c, r) = packed[packed_index(D, r, c)];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(A, Eigen::EigenvaluesOnly);
    return es.eigenvalues().maxCoeff();
  };
  require(m >= 1 && m <= 3, "track_index_keys",
          "spatial dimension must be 1, 2 or 3, got " + std::to_string(m));
  parallel_for_range(n, 64, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      double* mean = &keys.mean_position[i * m];
      double var = 0.0;
      int32_t count = 0;
      const auto t = static_cast<int32_t>(i);
      const AlignedTracks::Span sp = x.span(t);
      for (int32_t k = sp.begin; k < sp.end; ++k) {
        const int64_t cell = x.cell_base(t) + k;
        if (!x.valid[cell]) continue;
        ++count;
        for (int c = 0; c < m; ++c) mean[c] += x.state_at(cell)[c];
        var = std::max(var, max_eigenvalue(x.cov_at(cell)));
      }
      if (count > 0)
        for (int c = 0; c < m; ++c) mean[c] /= count;
      double r2 = 0.0;  // largest distance of a valid position from the mean
      for (int32_t k = sp.begin; k < sp.end; ++k) {
        const int64_t cell = x.cell_base(t) + k;
        if (!x.valid[cell]) continue;
        const double* xs = x.state_at(cell);
        double d2 = 0.0;
        for (int c = 0; c < m; ++c) d2 += (xs[c] - mean[c]) * (xs[c] - mean[c]);
        r2 = std::max(r2, d2);
      }
      keys.trajectory_radius[i] = std::sqrt(r2);
      keys.valid_times[i] = count;
      keys.max_position_variance[i] = var;
    }
  });
  return keys;
}

namespace {

// ρ(K') = χ²_p(D·K') / K' for K' = 0..K (index 0 unused), scaled by radius_scale².
std::vector<double> radius_factors(int D, int32_t K, const CandidateOptions& o) {
  std::vector<double> f(K + 1, 0.0);
  for (int32_t k = 1; k <= K; ++k)
    f[k] = chi_square_quantile(o.gate_probability, D * k) / k * o.radius_scale * o.radius_scale;
  return f;
}

// The bound of the header: full pairs (both tracks valid at all K common times) use
// d² ≤ (σ²_a + σ²_b)·ρ(K); any other pair the conservative d ≤ √((σ²_a + σ²_b)·ρ(1)) + s·(r_a + r_b).
bool within_bound(const TrackIndexKeys& ka, std::size_t i, const TrackIndexKeys& kb, std::size_t j,
                  const std::vector<double>& factor, double scale) {
  const int32_t va = ka.valid_times[i], vb = kb.valid_times[j];
  if (va == 0 || vb == 0) return false;
  const int m = ka.spatial_dim;
  double d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    const double d = ka.mean_position[i * m + c] - kb.mean_position[j * m + c];
    d2 += d * d;
  }
  const double var = ka.max_position_variance[i] + kb.max_position_variance[j];
  const int32_t K = static_cast<int32_t>(factor.size()) - 1;
  if (va == K && vb == K) return d2 <= var * factor[K];
  const double r = std::sqrt(var * factor[1]) + scale * (ka.trajectory_radius[i] + kb.trajectory_radius[j]);
  return d2 <= r * r;
}

// The exact form of the bound for a pair that is not full: the means over the pair's own common
// valid set V (K' = |V|), |m̄_a(V) − m̄_b(V)|² ≤ (σ²_a + σ²_b)·ρ(K'). O(|span_a ∩ span_b|·m) per pair, against
// O(K·D³) for λ: it removes most of the conservative radius' extra candidates before λ.
bool within_pair_bound(const AlignedTracks& a, std::size_t i, const AlignedTracks& b, std::size_t j,
                       const TrackIndexKeys& ka, const TrackIndexKeys& kb,
                       const std::vector<double>& factor) {
  const int m = ka.spatial_dim;
  std::array<double, 3> diff{0.0, 0.0, 0.0};
  int32_t common = 0;
  const auto ti = static_cast<int32_t>(i), tj = static_cast<int32_t>(j);
  const AlignedTracks::Span both = common_span(a.span(ti), b.span(tj));
  const int64_t base_a = a.cell_base(ti), base_b = b.cell_base(tj);
  for (int32_t k = both.begin; k < both.end; ++k) {
    const int64_t ca = base_a + k, cb = base_b + k;
    if (!a.valid[ca] || !b.valid[cb]) continue;
    ++common;
    const double *xa = a.state_at(ca), *xb = b.state_at(cb);
    for (int c = 0; c < m; ++c) diff[c] += xa[c] - xb[c];
  }
  if (common == 0) return false;  // never together: dof = 0, outside every gate
  double d2 = 0.0;
  for (int c = 0; c < m; ++c) d2 += (diff[c] / common) * (diff[c] / common);
  return d2 <= (ka.max_position_variance[i] + kb.max_position_variance[j]) * factor[common];
}

void check_pair_inputs(const AlignedTracks& a, const AlignedTracks& b) {
  require(a.dim == b.dim, "gated_candidate_pairs", "state dimensions differ");
  require(a.n_times == b.n_times, "gated_candidate_pairs", "numbers of common times differ");
  a.check_layout("gated_candidate_pairs");
  b.check_layout("gated_candidate_pairs");
}

using Cell = GridCell;
constexpr auto cell_of = grid_cell_of;

}  // namespace

namespace {

// For every i in a_set, appends to rows[i] the j in b_set within the bound, found through a
// uniform grid of cell size h over b_set's mean positions (h ≥ every radius these pairs can have,
// so the 3^m neighbouring cells hold all of them).
void grid_pass(const AlignedTracks& a, const TrackIndexKeys& ka, const std::vector<int32_t>& a_set,
               const AlignedTracks& b, const TrackIndexKeys& kb, const std::vector<int32_t>& b_set, double h,
               const std::vector<double>& factor, double scale, std::vector<std::vector<int32_t>>& rows) {
  if (a_set.empty() || b_set.empty()) return;
  if (!(h > 0.0) || !std::isfinite(h)) h = 1e-9;  // zero covariances: only coincident means match
  const int m = ka.spatial_dim;
  std::vector<std::pair<Cell, int32_t>> cells(b_set.size());
  for (std::size_t q = 0; q < b_set.size(); ++q)
    cells[q] = {cell_of(&kb.mean_position[static_cast<std::size_t>(b_set[q]) * m], m, h), b_set[q]};
  std::sort(cells.begin(), cells.end());  // by cell, then track: deterministic
  const int span_y = m >= 2 ? 1 : 0, span_z = m == 3 ? 1 : 0;
  parallel_for_range(a_set.size(), 256, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const int32_t i = a_set[q];
      const Cell c = cell_of(&ka.mean_position[static_cast<std::size_t>(i) * m], m, h);
      std::vector<int32_t>& row = rows[i];
      for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -span_y; dy <= span_y; ++dy)
          for (int64_t dz = -span_z; dz <= span_z; ++dz) {
            const Cell key{c[0] + dx, c[1] + dy, c[2] + dz};
            auto it = std::lower_bound(cells.begin(), cells.end(),
                                       std::make_pair(key, std::numeric_limits<int32_t>::min()));
            for (; it != cells.end() && it->first == key; ++it)
              if (within_bound(ka, i, kb, it->second, factor, scale) &&
                  within_pair_bound(a, i, b, it->second, ka, kb, factor))
                row.push_back(it->second);
          }
    }
  });
}

}  // namespace

CandidatePairs gated_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b,
                                     const CandidateOptions& options) {
  options.validate();
  check_pair_inputs(a, b);
  CandidatePairs out;
  out.n_a = a.n_tracks();
  out.n_b = b.n_tracks();
  if (out.n_a == 0 || out.n_b == 0) return out;
  const TrackIndexKeys ka = track_index_keys(a), kb = track_index_keys(b);
  const std::vector<double> factor = radius_factors(a.dim, a.n_times, options);
  const int32_t K = a.n_times;

  // Full tracks (valid at every common time) and partial ones, with their largest σ² and radius.
  struct Split {
    std::vector<int32_t> full, partial, all;
    double var_full = 0.0, var_all = 0.0, radius_all = 0.0;
  };
  auto split = [&](const TrackIndexKeys& k, int32_t n) {
    Split s;
    for (int32_t i = 0; i < n; ++i) {
      if (k.valid_times[i] == 0) continue;
      (k.valid_times[i] == K ? s.full : s.partial).push_back(i);
      s.all.push_back(i);
      s.var_all = std::max(s.var_all, k.max_position_variance[i]);
      s.radius_all = std::max(s.radius_all, k.trajectory_radius[i]);
      if (k.valid_times[i] == K) s.var_full = std::max(s.var_full, k.max_position_variance[i]);
    }
    return s;
  };
  const Split sa = split(ka, out.n_a), sb = split(kb, out.n_b);
  std::vector<std::vector<int32_t>> rows(out.n_a);
  // Full × full: the tight radius. Pairs with a partial track: the conservative radius.
  grid_pass(a, ka, sa.full, b, kb, sb.full, std::sqrt((sa.var_full + sb.var_full) * factor[K]), factor,
            options.radius_scale, rows);
  const double h_partial = std::sqrt((sa.var_all + sb.var_all) * factor[1]) +
                           options.radius_scale * (sa.radius_all + sb.radius_all);
  grid_pass(a, ka, sa.partial, b, kb, sb.all, h_partial, factor, options.radius_scale, rows);
  grid_pass(a, ka, sa.full, b, kb, sb.partial, h_partial, factor, options.radius_scale, rows);

  std::size_t total = 0;
  for (auto& r : rows) {
    std::sort(r.begin(), r.end());  // the three passes hold disjoint pairs
    total += r.size();
  }
  out.a.reserve(total);
  out.b.reserve(total);
  for (int32_t i = 0; i < out.n_a; ++i) {
    out.a.insert(out.a.end(), rows[i].size(), i);
    out.b.insert(out.b.end(), rows[i].begin(), rows[i].end());
    std::vector<int32_t>().swap(rows[i]);
  }
  return out;
}

CandidatePairs gated_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b,
                                               const CandidateOptions& options) {
  options.validate();
  check_pair_inputs(a, b);
  CandidatePairs out;
  out.n_a = a.n_tracks();
  out.n_b = b.n_tracks();
  const TrackIndexKeys ka = track_index_keys(a), kb = track_index_keys(b);
  const std::vector<double> factor = radius_factors(a.dim, a.n_times, options);
  for (int32_t i = 0; i < out.n_a; ++i)
    for (int32_t j = 0; j < out.n_b; ++j)
      if (within_bound(ka, i, kb, j, factor, options.radius_scale) &&
          within_pair_bound(a, i, b, j, ka, kb, factor)) {
        out.a.push_back(i);
        out.b.push_back(j);
      }
  return out;
}

int64_t SparsePairStatistic::find(int32_t ia, int32_t ib) const {
  std::size_t lo = 0, hi = a.size();
  while (lo < hi) {  // first q with (a, b)[q] >= (ia, ib)
    const std::size_t mid = (lo + hi) / 2;
    if (a[mid] < ia || (a[mid] == ia && b[mid] < ib))
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < a.size() && a[lo] == ia && b[lo] == ib ? static_cast<int64_t>(lo) : -1;
}

void copy_rows(const AlignedTracks& x, std::span<const int32_t> rows, AlignedTracks& out) {
  const int D = x.dim, P = packed_size(D);
  out.sensor = x.sensor;
  out.dim = x.dim;
  out.n_times = x.n_times;
  out.times = x.times;
  out.track.resize(rows.size());
  out.truth.resize(rows.size());
  std::vector<int32_t> begin(rows.size()), length(rows.size());
  for (std::size_t q = 0; q < rows.size(); ++q) {
    const AlignedTracks::Span sp = x.span(rows[q]);
    begin[q] = sp.begin;
    length[q] = sp.size();
  }
  out.allocate(begin, length);
  for (std::size_t q = 0; q < rows.size(); ++q) {
    const std::size_t r = rows[q];
    out.track[q] = x.track[r];
    out.truth[q] = r < x.truth.size() ? x.truth[r] : -1;
    const auto from = static_cast<std::size_t>(x.span_offset[r]),
               to = static_cast<std::size_t>(out.span_offset[q]);
    const auto n = static_cast<std::size_t>(length[q]);
    std::copy_n(x.state.data() + from * D, n * D, out.state.data() + to * D);
    std::copy_n(x.cov.data() + from * P, n * P, out.cov.data() + to * P);
    std::copy_n(x.valid.data() + from, n, out.valid.data() + to);
  }
}

SparsePairStatistic sparse_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                                const CandidatePairs& pairs,
                                                const StatisticOptions& options) {
  options.validate();
  check_pair_inputs(a, b);
  require(pairs.n_a == a.n_tracks() && pairs.n_b == b.n_tracks() && pairs.a.size() == pairs.b.size(),
          "sparse_sequential_statistic", "the candidate pairs do not belong to these aligned tracks");
  SparsePairStatistic s;
  s.n_a = pairs.n_a;
  s.n_b = pairs.n_b;
  s.a = pairs.a;
  s.b = pairs.b;
  const std::size_t n = pairs.size();
  s.lambda.assign(n, 0.0);
  s.dof.assign(n, 0);
  s.in_gate.assign(n, 0);
  for (std::size_t q = 0; q < n; ++q) {
    require(pairs.a[q] >= 0 && pairs.a[q] < pairs.n_a && pairs.b[q] >= 0 && pairs.b[q] < pairs.n_b,
            "sparse_sequential_statistic", [&] { return "pair " + std::to_string(q) + " is out of range"; });
    require(q == 0 || pairs.a[q] > pairs.a[q - 1] ||
                (pairs.a[q] == pairs.a[q - 1] && pairs.b[q] > pairs.b[q - 1]),
            "sparse_sequential_statistic", "pairs must be sorted by (a, b) without repeats");
  }
  // Row ranges [row_begin[r], row_begin[r+1]) of pairs with a = distinct row r.
  std::vector<std::size_t> row_begin;
  for (std::size_t q = 0; q < n; ++q)
    if (q == 0 || pairs.a[q] != pairs.a[q - 1]) row_begin.push_back(q);
  row_begin.push_back(n);
  const SequentialGate gate = sequential_gate_for(a, b, options);  // one set of χ² thresholds for all rows
  parallel_for_range(row_begin.size() - 1, 16, [&](std::size_t lo, std::size_t hi) {
    AlignedTracks one, many;
    for (std::size_t r = lo; r < hi; ++r) {
      const std::size_t q0 = row_begin[r], q1 = row_begin[r + 1];
      const int32_t ia = pairs.a[q0];
      copy_rows(a, std::span<const int32_t>(&ia, 1), one);
      copy_rows(b, std::span<const int32_t>(&pairs.b[q0], q1 - q0), many);
      // seed 000 Eq. 1–2 and the gate of the dense kernel (one SequentialGate decides both).
      const PairStatistic ps = independent_sequential_statistic(one, many, options, gate);
      for (std::size_t q = q0; q < q1; ++q) {
        const std::size_t c = q - q0;
        s.lambda[q] = ps.lambda[c];
        s.dof[q] = ps.dof[c];
        s.in_gate[q] = ps.in_gate[c];
      }
    }
  });
  return s;
}

SparsePairStatistic keep_in_gate(const SparsePairStatistic& s) {
  SparsePairStatistic out;
  out.n_a = s.n_a;
  out.n_b = s.n_b;
  // Laid out at their number (the memory budget counts 21 bytes a kept pair, not a doubling's slack).
  const auto kept = static_cast<std::size_t>(
      std::count_if(s.in_gate.begin(), s.in_gate.end(), [](uint8_t g) { return g != 0; }));
  out.a.reserve(kept);
  out.b.reserve(kept);
  out.lambda.reserve(kept);
  out.dof.reserve(kept);
  out.in_gate.reserve(kept);
  for (std::size_t q = 0; q < s.size(); ++q)
    if (s.in_gate[q]) {
      out.a.push_back(s.a[q]);
      out.b.push_back(s.b[q]);
      out.lambda.push_back(s.lambda[q]);
      out.dof.push_back(s.dof[q]);
      out.in_gate.push_back(1);
    }
  return out;
}

}  // namespace trackassoc
