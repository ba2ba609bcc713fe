// The candidates of a gate: the count filter's table, the position-bound prune and the index per
// gate; see kernels/statistics/gate_candidates.hpp.
#include "kernels/statistics/gate_candidates.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/core/parallel.hpp"

namespace trackassoc {
namespace {

// The position block's term d_pᵀ C_pp⁻¹ d_p of the states xa, xb (dimension D, positions the
// first m ≤ 3 components) with C = P_a + P_b (packed covariances pa, pb), by Cholesky; false when
// C_pp is not positive definite. It is at most the full dᵀC⁻¹d, so the prune may sum it capped;
// the index's per-scan bound (scan_candidates.hpp) is this term at most c, tested there by the
// adjugate as a superset.
bool position_block_term(const double* xa, const double* pa, const double* xb, const double* pb, int D, int m,
                         double& term) {
  double L[3][3] = {}, y[3] = {};
  for (int r = 0; r < m; ++r)
    for (int c = 0; c <= r; ++c) {
      double v = pa[packed_index(D, c, r)] + pb[packed_index(D, c, r)];
      for (int t = 0; t < c; ++t) v -= L[r][t] * L[c][t];
      if (r == c) {
        if (!(v > 0.0)) return false;
        L[r][r] = std::sqrt(v);
      } else {
        L[r][c] = v / L[c][c];
      }
    }
  term = 0.0;
  for (int r = 0; r < m; ++r) {
    double v = xa[r] - xb[r];
    for (int t = 0; t < r; ++t) v -= L[r][t] * y[t];
    y[r] = v / L[r][r];
    term += y[r] * y[r];
  }
  return true;
}

}  // namespace

CandidatePairs prune_by_position_bound(const AlignedTracks& a, const AlignedTracks& b,
                                       const CandidatePairs& pairs, const StatisticOptions& statistic,
                                       AllocationGauge* gauge) {
  auto copy = [&] {  // the pairs unpruned: a copy of them
    gauge_add(gauge, static_cast<double>(pairs.size() * 2 * sizeof(int32_t)), true);
    return pairs;
  };
  if ((statistic.correlated && statistic.cross_correlation > 0.0) || statistic.common_process_noise > 0.0)
    return copy();  // the bound is for C = P_a + P_b
  const SequentialGate gate = sequential_gate_for(a, b, statistic);
  if (!gate.enabled()) return copy();
  gauge_add(gauge, static_cast<double>(pairs.size()), true);  // (sensor pairs are pruned in parallel)
  const int D = a.dim, m = D / 2;
  const double cap = gate.cap();
  const bool calibrated = statistic.gate == GateMethod::kCalibrated;
  const bool early = std::isfinite(cap);  // (kChiSquareSum: c = +inf)
  std::vector<uint8_t> keep(pairs.size(), 0);
  parallel_for_range(pairs.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t q = lo; q < hi; ++q) {
      const int32_t i = pairs.a[q], j = pairs.b[q];
      const AlignedTracks::Span both = common_span(a.span(i), b.span(j));
      const int64_t base_a = a.cell_base(i), base_b = b.cell_base(j);
      // With a finite cap (kCalibrated), a pair is kept without its remaining terms once its capped
      // sum so far and the cap at each scan left cannot exceed G(n) (with a scan below the cap),
      // its n common valid scans counted first; by a relative 10⁻¹² inside G(n), so that the sum's
      // round-off cannot make the decision differ from the full sum's. Terms computed: 54 % of the
      // pairs' common scans on the scale study's tracks (n = 1000), 75 % on recorded_10k's.
      int32_t n = 0;
      if (early)
        for (int32_t k = both.begin; k < both.end; ++k) n += a.valid[base_a + k] && b.valid[base_b + k];
      const double sure = early && n > 0 ? gate.threshold(n) * (1.0 - 1e-12) : 0.0;
      double bound = 0.0;
      int32_t seen = 0, below = 0;
      bool broken = false;
      for (int32_t k = both.begin; k < both.end; ++k) {
        const int64_t ca = base_a + k, cb = base_b + k;
        if (!a.valid[ca] || !b.valid[cb]) continue;
        ++seen;
        // d_pᵀ C_pp⁻¹ d_p ≤ dᵀC⁻¹d: the position block alone (m ≤ 3).
        double term = 0.0;
        if (!position_block_term(a.state_at(ca), a.cov_at(ca), b.state_at(cb), b.cov_at(cb), D, m, term)) {
          broken = true;  // leave the decision (and the error message) to the full statistic
          break;
        }
        below += term <= cap;
        bound += std::min(term, cap);
        if (early && below > 0 && bound + (n - seen) * cap <= sure) break;
      }
      if (!early) n = seen;
      keep[q] = broken || (n > 0 && bound <= gate.threshold(n) && (!calibrated || below > 0));
    }
  });
  // The pairs kept, counted and then laid out at their size (8 bytes a pair) beside the flags.
  const auto kept = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), uint8_t{1}));
  gauge_add(gauge, static_cast<double>(kept * 2 * sizeof(int32_t)), true);
  CandidatePairs out;
  out.n_a = pairs.n_a;
  out.n_b = pairs.n_b;
  out.a.reserve(kept);
  out.b.reserve(kept);
  for (std::size_t q = 0; q < pairs.size(); ++q)
    if (keep[q]) {
      out.a.push_back(pairs.a[q]);
      out.b.push_back(pairs.b[q]);
    }
  std::vector<uint8_t>().swap(keep);
  gauge_release(gauge, static_cast<double>(pairs.size()));
  return out;
}

CandidatePairs candidate_pairs_for_gate(const AlignedTracks& a, const AlignedTracks& b,
                                        const StatisticOptions& statistic, double radius_scale) {
  if (statistic.gate == GateMethod::kCalibrated)
    return scan_candidate_pairs(a, b, SequentialGate(a.dim, statistic).cap(), radius_scale);
  return gated_candidate_pairs(a, b, CandidateOptions{statistic.gate_probability, radius_scale});
}

std::vector<int32_t> least_scans_within_bound(int dim, const StatisticOptions& statistic, int32_t max_scans) {
  if (statistic.gate != GateMethod::kCalibrated ||
      (statistic.correlated && statistic.cross_correlation > 0.0) || statistic.common_process_noise > 0.0 ||
      max_scans < 1)
    return {};  // (prune_by_position_bound's conditions: the bound is for C = P_a + P_b)
  const SequentialGate gate(dim, statistic, max_scans);
  if (!gate.enabled()) return {};
  const double c = gate.cap();
  std::vector<int32_t> least(static_cast<std::size_t>(max_scans) + 1, 1);
  for (int32_t n = 1; n <= max_scans; ++n) {
    // (n − h)·c ≤ G(n), with a relative 10⁻⁹ for the round-off of the prune's sum of capped terms.
    const double allowed_misses = (gate.threshold(n) * (1.0 + 1e-9) + 1e-9) / c;
    least[n] = std::max<int32_t>(1, static_cast<int32_t>(std::ceil(n - allowed_misses)));
  }
  for (int32_t n = max_scans - 1; n >= 0; --n)
    least[n] = std::min(least[n], least[n + 1]);  // a lower bound of n
  return least;
}

std::vector<CandidatePairs> candidate_pairs_for_gate(std::span<const AlignedTracks* const> sensors,
                                                     const StatisticOptions& statistic, double radius_scale,
                                                     AllocationGauge* gauge,
                                                     std::vector<std::size_t>* found) {
  if (statistic.gate == GateMethod::kCalibrated && !sensors.empty()) {
    // A pair's common scans are at most the shorter of its sensors' longest spans, so at most the
    // second largest of the longest spans.
    int32_t most = 0, second = 0;
    for (const AlignedTracks* x : sensors) {
      const int32_t l = std::min(longest_span(*x), sensors[0]->n_times);
      if (l > most)
        second = most, most = l;
      else
        second = std::max(second, l);
    }
    const std::vector<int32_t> least = least_scans_within_bound(sensors[0]->dim, statistic, second);
    return scan_candidate_pairs(sensors, SequentialGate(sensors[0]->dim, statistic).cap(), radius_scale,
                                gauge, least, found);
  }
  const std::size_t S = sensors.size();
  std::vector<CandidatePairs> out(S * S);
  if (found) found->assign(S * S, 0);
  for (std::size_t s = 0; s < S; ++s)
    for (std::size_t t = s + 1; t < S; ++t) {
      // The time-averaged index's own transient is not gauged (the pairs are counted once found).
      out[s * S + t] = candidate_pairs_for_gate(*sensors[s], *sensors[t], statistic, radius_scale);
      gauge_add(gauge, static_cast<double>(out[s * S + t].size() * 2 * sizeof(int32_t)));
      if (found) (*found)[s * S + t] = out[s * S + t].size();
    }
  return out;
}

}  // namespace trackassoc
