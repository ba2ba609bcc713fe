// Sparse gated candidates: the grid index and λ on candidate pairs. See the header for the bound.
#include "kernels/sparse_candidates.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "kernels/error.hpp"
#include "kernels/parallel.hpp"

namespace trackassoc {

void CandidateOptions::validate() const {
  require(gate_probability > 0.0 && gate_probability < 1.0, "CandidateOptions.gate_probability",
          "the sparse form needs a chi-square gate in (0, 1) (1 would make every pair a candidate), got " +
              std::to_string(gate_probability));
  require(std::isfinite(radius_scale) && radius_scale >= 1.0, "CandidateOptions.radius_scale",
          "must be finite and >= 1, got " + std::to_string(radius_scale));
}

TrackIndexKeys track_index_keys(const AlignedTracks& x) {
  const int D = x.dim, P = packed_size(D), m = D / 2;
  const int32_t n = x.n_tracks(), K = x.n_times;
  TrackIndexKeys keys;
  keys.spatial_dim = m;
  keys.mean_position.assign(static_cast<std::size_t>(n) * m, 0.0);
  keys.max_position_variance.assign(n, 0.0);
  keys.valid_times.assign(n, 0);
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
  require(m >= 1 && m <= 3, "track_index_keys", "spatial dimension must be 1, 2 or 3, got " + std::to_string(m));
  parallel_for_range(n, 64, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      double* mean = &keys.mean_position[i * m];
      double var = 0.0;
      int32_t count = 0;
      for (int32_t k = 0; k < K; ++k) {
        const std::size_t cell = i * K + k;
        if (!x.valid[cell]) continue;
        ++count;
        for (int c = 0; c < m; ++c) mean[c] += x.state[cell * D + c];
        var = std::max(var, max_eigenvalue(&x.cov[cell * P]));
      }
      if (count > 0)
        for (int c = 0; c < m; ++c) mean[c] /= count;
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
  for (int32_t k = 1; k <= K; ++k) f[k] = chi_square_quantile(o.gate_probability, D * k) / k * o.radius_scale * o.radius_scale;
  return f;
}

bool within_bound(const TrackIndexKeys& ka, std::size_t i, const TrackIndexKeys& kb, std::size_t j,
                  const std::vector<double>& factor) {
  const int32_t kv = std::min(ka.valid_times[i], kb.valid_times[j]);
  if (kv == 0) return false;
  const int m = ka.spatial_dim;
  double d2 = 0.0;
  for (int c = 0; c < m; ++c) {
    const double d = ka.mean_position[i * m + c] - kb.mean_position[j * m + c];
    d2 += d * d;
  }
  return d2 <= (ka.max_position_variance[i] + kb.max_position_variance[j]) * factor[kv];
}

void check_pair_inputs(const AlignedTracks& a, const AlignedTracks& b) {
  require(a.dim == b.dim, "gated_candidate_pairs", "state dimensions differ");
  require(a.n_times == b.n_times, "gated_candidate_pairs", "numbers of common times differ");
  for (const AlignedTracks* x : {&a, &b}) {
    const std::size_t cells = static_cast<std::size_t>(x->n_tracks()) * x->n_times;
    require(x->valid.size() == cells && x->state.size() == cells * x->dim &&
                x->cov.size() == cells * packed_size(x->dim),
            "gated_candidate_pairs", "aligned tracks of sensor " + std::to_string(x->sensor) + " are inconsistent");
  }
}

using Cell = std::array<int64_t, 3>;

Cell cell_of(const double* p, int m, double h) {
  Cell c{0, 0, 0};
  constexpr double kLimit = 4.0e18;
  for (int d = 0; d < m; ++d) c[d] = static_cast<int64_t>(std::clamp(std::floor(p[d] / h), -kLimit, kLimit));
  return c;
}

}  // namespace

CandidatePairs gated_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, const CandidateOptions& options) {
  options.validate();
  check_pair_inputs(a, b);
  CandidatePairs out;
  out.n_a = a.n_tracks();
  out.n_b = b.n_tracks();
  if (out.n_a == 0 || out.n_b == 0) return out;
  const TrackIndexKeys ka = track_index_keys(a), kb = track_index_keys(b);
  const int m = ka.spatial_dim;
  const std::vector<double> factor = radius_factors(a.dim, a.n_times, options);

  // Cell size: the largest radius any pair can have (smallest valid count → largest factor).
  auto min_valid = [](const TrackIndexKeys& k) {
    int32_t v = std::numeric_limits<int32_t>::max();
    for (int32_t c : k.valid_times)
      if (c > 0) v = std::min(v, c);
    return v;
  };
  const int32_t va = min_valid(ka), vb = min_valid(kb);
  if (va == std::numeric_limits<int32_t>::max() || vb == std::numeric_limits<int32_t>::max()) return out;
  const double var_a = *std::max_element(ka.max_position_variance.begin(), ka.max_position_variance.end());
  const double var_b = *std::max_element(kb.max_position_variance.begin(), kb.max_position_variance.end());
  double h = std::sqrt((var_a + var_b) * factor[std::min(va, vb)]);
  if (!(h > 0.0) || !std::isfinite(h)) h = 1e-9;  // zero covariances: only coincident means match

  // Tracks of b sorted by cell (then index: deterministic).
  std::vector<Cell> cell_b(out.n_b);
  std::vector<int32_t> order;
  order.reserve(out.n_b);
  for (int32_t j = 0; j < out.n_b; ++j)
    if (kb.valid_times[j] > 0) {
      cell_b[j] = cell_of(&kb.mean_position[static_cast<std::size_t>(j) * m], m, h);
      order.push_back(j);
    }
  std::sort(order.begin(), order.end(), [&](int32_t x, int32_t y) {
    return cell_b[x] != cell_b[y] ? cell_b[x] < cell_b[y] : x < y;
  });
  std::vector<Cell> sorted_cells(order.size());
  for (std::size_t q = 0; q < order.size(); ++q) sorted_cells[q] = cell_b[order[q]];

  // Per row of a: its candidates, gathered in parallel, then concatenated in row order.
  std::vector<std::vector<int32_t>> rows(out.n_a);
  parallel_for_range(out.n_a, 256, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      if (ka.valid_times[i] == 0) continue;
      const Cell c = cell_of(&ka.mean_position[i * m], m, h);
      std::vector<int32_t>& row = rows[i];
      const int span_z = m == 3 ? 1 : 0;
      for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -1; dy <= 1; ++dy)
          for (int64_t dz = -span_z; dz <= span_z; ++dz) {
            const Cell q{c[0] + dx, c[1] + dy, c[2] + dz};
            auto range = std::equal_range(sorted_cells.begin(), sorted_cells.end(), q);
            for (auto it = range.first; it != range.second; ++it) {
              const int32_t j = order[it - sorted_cells.begin()];
              if (within_bound(ka, i, kb, j, factor)) row.push_back(j);
            }
          }
      std::sort(row.begin(), row.end());
    }
  });
  std::size_t total = 0;
  for (const auto& r : rows) total += r.size();
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
      if (within_bound(ka, i, kb, j, factor)) {
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

namespace {

// Copies the aligned rows `rows` of `x` into a new AlignedTracks (same times and dim).
void copy_rows(const AlignedTracks& x, std::span<const int32_t> rows, AlignedTracks& out) {
  const int D = x.dim, P = packed_size(D);
  const std::size_t K = x.n_times;
  out.sensor = x.sensor;
  out.dim = x.dim;
  out.n_times = x.n_times;
  out.track.resize(rows.size());
  out.truth.resize(rows.size());
  out.state.resize(rows.size() * K * D);
  out.cov.resize(rows.size() * K * P);
  out.valid.resize(rows.size() * K);
  for (std::size_t q = 0; q < rows.size(); ++q) {
    const std::size_t r = rows[q];
    out.track[q] = x.track[r];
    out.truth[q] = r < x.truth.size() ? x.truth[r] : -1;
    std::copy_n(&x.state[r * K * D], K * D, &out.state[q * K * D]);
    std::copy_n(&x.cov[r * K * P], K * P, &out.cov[q * K * P]);
    std::copy_n(&x.valid[r * K], K, &out.valid[q * K]);
  }
}

}  // namespace

SparsePairStatistic sparse_sequential_statistic(const AlignedTracks& a, const AlignedTracks& b,
                                                const CandidatePairs& pairs, const StatisticOptions& options) {
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
            "sparse_sequential_statistic", "pair " + std::to_string(q) + " is out of range");
    require(q == 0 || pairs.a[q] > pairs.a[q - 1] || (pairs.a[q] == pairs.a[q - 1] && pairs.b[q] > pairs.b[q - 1]),
            "sparse_sequential_statistic", "pairs must be sorted by (a, b) without repeats");
  }
  // Gate thresholds χ²_p(D·k) once for all rows (the sub-problems run with the gate off).
  const int32_t K = a.n_times;
  std::vector<double> threshold(K + 1, std::numeric_limits<double>::infinity());
  if (options.gate_probability < 1.0)
    for (int32_t k = 1; k <= K; ++k) threshold[k] = chi_square_quantile(options.gate_probability, a.dim * k);
  StatisticOptions sub = options;
  sub.gate_probability = 1.0;

  // Row ranges [row_begin[r], row_begin[r+1]) of pairs with a = distinct row r.
  std::vector<std::size_t> row_begin;
  for (std::size_t q = 0; q < n; ++q)
    if (q == 0 || pairs.a[q] != pairs.a[q - 1]) row_begin.push_back(q);
  row_begin.push_back(n);
  parallel_for_range(row_begin.size() - 1, 16, [&](std::size_t lo, std::size_t hi) {
    AlignedTracks one, many;
    for (std::size_t r = lo; r < hi; ++r) {
      const std::size_t q0 = row_begin[r], q1 = row_begin[r + 1];
      const int32_t ia = pairs.a[q0];
      copy_rows(a, std::span<const int32_t>(&ia, 1), one);
      copy_rows(b, std::span<const int32_t>(&pairs.b[q0], q1 - q0), many);
      const PairStatistic ps = independent_sequential_statistic(one, many, sub);  // seed 000 Eq. 1–2
      for (std::size_t q = q0; q < q1; ++q) {
        const std::size_t c = q - q0;
        s.lambda[q] = ps.lambda[c];
        s.dof[q] = ps.dof[c];
        const int32_t times = a.dim > 0 ? ps.dof[c] / a.dim : 0;
        s.in_gate[q] = times > 0 && ps.lambda[c] <= threshold[times];
      }
    }
  });
  return s;
}

SparsePairStatistic keep_in_gate(const SparsePairStatistic& s) {
  SparsePairStatistic out;
  out.n_a = s.n_a;
  out.n_b = s.n_b;
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
