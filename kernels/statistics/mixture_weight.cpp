// A two-component mixture's weight by bisection on the score; see kernels/statistics/mixture_weight.hpp.
#include "kernels/statistics/mixture_weight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "kernels/core/golden_section.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

double mixture_weight(std::span<const float> log_ratios, double prior, double prior_weight) {
  if (!(prior > 0.0 && prior < 1.0) || log_ratios.empty()) return prior;
  // ℓ'(π): each sample's (e^d − 1) / (1 − π + π e^d), written for d > 0 as (1 − e^−d) / ((1 − π) e^−d + π)
  // so that neither form overflows.
  auto score = [&](double pi) {
    double s = prior_weight * prior / pi - prior_weight * (1.0 - prior) / (1.0 - pi);
    for (float value : log_ratios) {
      const double d = value;
      if (d > 0.0) {
        const double e = std::exp(-d);
        s += (1.0 - e) / ((1.0 - pi) * e + pi);
      } else {
        const double e = std::exp(d);
        s += (e - 1.0) / (1.0 - pi + pi * e);
      }
    }
    return s;
  };
  constexpr double kFloor = 1e-6;
  double lo = kFloor, hi = 1.0 - kFloor;
  const double at_lo = score(lo), at_hi = score(hi);
  if (at_lo == 0.0 && at_hi == 0.0) return prior;  // ℓ flat: nothing tells π apart
  if (at_lo <= 0.0) return lo;
  if (at_hi >= 0.0) return hi;
  for (int halving = 0; halving < 60; ++halving) {
    const double mid = 0.5 * (lo + hi);
    (score(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

double logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }

}  // namespace

SpanMixtureWeight span_mixture_weight(std::span<const float> log_ratios, std::span<const float> spans,
                                      double prior, double prior_weight) {
  if (log_ratios.size() != spans.size())
    throw std::invalid_argument("span_mixture_weight: one span per log-ratio");
  for (float s : spans)
    if (!(s >= 0.0f) || !std::isfinite(s))
      throw std::invalid_argument("span_mixture_weight: spans must be finite and >= 0");
  SpanMixtureWeight best;
  best.constant = prior;
  const std::size_t J = log_ratios.size();
  if (J == 0 || !(prior > 0.0 && prior < 1.0)) return best;
  // One span only: the samples say nothing of how π changes with it, and only π(s) is determined;
  // the constant that explains them is mixture_weight's.
  const auto [shortest, longest] = std::minmax_element(spans.begin(), spans.end());
  if (*longest == *shortest) {
    best.constant = mixture_weight(log_ratios, prior, prior_weight);
    best.mean_span = *shortest;
    return best;
  }
  const std::size_t stride = (J + kMaxSamples - 1) / kMaxSamples;
  std::vector<double> d, s, e;  // e: e^d for d ≤ 0, e^−d for d > 0 (computed once)
  for (std::size_t j = 0; j < J; j += stride) {
    d.push_back(log_ratios[j]), s.push_back(spans[j]);
    e.push_back(std::exp(-std::fabs(d.back())));
  }
  const double weight = static_cast<double>(J) / static_cast<double>(d.size());
  double span_sum = 0.0;
  for (double x : s) span_sum += x;
  const double mean = span_sum / static_cast<double>(s.size());
  best.mean_span = mean;
  const double scale = mean > 0.0 ? mean : 1.0;  // λ is searched as λ s̄
  // ℓ at π_c = logistic(u) given each sample's e^{−λ s_j} (decay): the samples' terms and the
  // prior's, w/J pseudo-samples at π₀ at each sample's span. With q = 1 − π(s) = (1 − π_c) e^{−λ s},
  // ln(1 − π + π e^d) = ln(q + (1 − q) e^d) (for d > 0: d + ln(q e^−d + 1 − q)).
  auto at_decay = [&](double u, double rate, const std::vector<double>& decay) {
    const double log_quiet = -std::log1p(std::exp(u)), quiet = std::exp(log_quiet);  // 1 − π_c
    double l = 0.0, log_pi = 0.0;
    for (std::size_t j = 0; j < d.size(); ++j) {
      const double q = quiet * decay[j], pi = 1.0 - q;
      l += d[j] > 0.0 ? d[j] + std::log(q * e[j] + pi) : std::log(q + pi * e[j]);
      log_pi += std::log(pi);
    }
    // Σ_j ln(1 − π(s_j)) = J ln(1 − π_c) − λ Σ_j s_j.
    const double log_q = static_cast<double>(d.size()) * log_quiet - rate * span_sum;
    return weight * l +
           prior_weight * (prior * log_pi + (1.0 - prior) * log_q) / static_cast<double>(d.size());
  };
  auto set_rate = [&](double v, std::vector<double>& decay) {  // ln(λ s̄) = v (−inf: λ = 0); returns λ
    const double rate = std::isinf(v) ? 0.0 : std::exp(v) / scale;
    decay.resize(s.size());
    for (std::size_t j = 0; j < s.size(); ++j) decay[j] = std::exp(-rate * s[j]);
    return rate;
  };
  const double u_lo = std::log(1e-6 / (1.0 - 1e-6)), u_hi = -u_lo, v_lo = std::log(1e-3),
               v_hi = std::log(1e2);
  constexpr int kU = 20, kV = 20;
  const double du = (u_hi - u_lo) / (kU - 1), dv = (v_hi - v_lo) / (kV - 1);
  auto v_at = [&](int b) {  // column b of the grid: λ = 0, then kV rates
    return b == 0 ? -std::numeric_limits<double>::infinity() : v_lo + (v_hi - v_lo) * (b - 1) / (kV - 1);
  };
  auto golden = [](double lo, double hi, int steps, auto&& f) {  // the maximum of f on [lo, hi]
    const auto [a, b] = golden_section_bracket([&](double x) { return -f(x); }, lo, hi, 0.0, steps);
    return 0.5 * (a + b);
  };
  // π_c's best at a given rate near u: a golden section over a grid step either side.
  auto refine_u = [&](double rate, const std::vector<double>& decay, double& u, int steps) {
    const double x = golden(std::max(u_lo, u - du), std::min(u_hi, u + du), steps,
                            [&](double y) { return at_decay(y, rate, decay); });
    const double l = at_decay(x, rate, decay), l0 = at_decay(u, rate, decay);
    if (l > l0) u = x;
    return std::max(l, l0);
  };
  // The grid, a column (a rate) per task (oneTBB, kernels/core/parallel.hpp): each column's best row.
  std::vector<double> column_best(kV + 1), column_u(kV + 1, u_lo);
  parallel_for_range(kV + 1, 1, [&](std::size_t first, std::size_t last) {
    std::vector<double> own;
    for (std::size_t b = first; b < last; ++b) {
      const double rate = set_rate(v_at(static_cast<int>(b)), own);
      column_best[b] = -std::numeric_limits<double>::infinity();
      for (int a = 0; a < kU; ++a)
        if (const double u = u_lo + du * a, l = at_decay(u, rate, own); l > column_best[b])
          column_best[b] = l, column_u[b] = u;
    }
  });
  // The three best columns (in column order on ties, so the answer does not depend on the threads)
  // with π_c refined; then the best one's rate between its neighbours, π_c re-fitted at each.
  std::vector<int> order(kV + 1);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return column_best[a] > column_best[b]; });
  std::vector<double> decay;
  int column = order[0];
  for (int k = 0; k < 3; ++k) {
    const int b = order[static_cast<std::size_t>(k)];
    const double rate = set_rate(v_at(b), decay);
    column_best[b] = refine_u(rate, decay, column_u[b], 30);
    if (column_best[b] > column_best[column] || (column_best[b] == column_best[column] && b < column))
      column = b;
  }
  double bu = column_u[column], bv = v_at(column);
  if (column > 0) {
    auto at_rate = [&](double v) {
      const double rate = set_rate(v, decay);
      double u = bu;
      return refine_u(rate, decay, u, 20);
    };
    const double v = golden(std::max(v_lo, bv - dv), std::min(v_hi, bv + dv), 12, at_rate);
    const double rate = set_rate(v, decay);
    double u = bu;
    if (refine_u(rate, decay, u, 30) > column_best[column]) bu = u, bv = v;
  }
  best.constant = logistic(bu);
  best.rate = std::isinf(bv) ? 0.0 : std::exp(bv) / scale;
  return best;
}

}  // namespace trackassoc
