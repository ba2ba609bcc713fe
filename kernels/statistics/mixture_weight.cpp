// A two-component mixture's weight by bisection on the score; see kernels/statistics/mixture_weight.hpp.
#include "kernels/statistics/mixture_weight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

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
  const std::size_t stride = (J + kMaxSamples - 1) / kMaxSamples;
  std::vector<double> d, s, e;  // e: e^d for d ≤ 0, e^−d for d > 0 (log_mixture's, computed once)
  for (std::size_t j = 0; j < J; j += stride) {
    d.push_back(log_ratios[j]), s.push_back(spans[j]);
    e.push_back(std::exp(-std::fabs(d.back())));
  }
  const double weight = static_cast<double>(J) / static_cast<double>(d.size());
  double mean = 0.0;
  for (double x : s) mean += x;
  mean /= static_cast<double>(s.size());
  best.mean_span = mean;
  const double scale = mean > 0.0 ? mean : 1.0;  // λ is searched as λ s̄
  // ℓ at π_c = logistic(u) given each sample's e^{−λ s_j} (decay).
  auto at_decay = [&](double u, double rate, const std::vector<double>& decay) {
    const double pc = logistic(u), at_mean = 1.0 - (1.0 - pc) * std::exp(-rate * mean);
    if (!(at_mean < 1.0)) return -std::numeric_limits<double>::infinity();
    double l = 0.0;
    for (std::size_t j = 0; j < d.size(); ++j) {
      const double pi = 1.0 - (1.0 - pc) * decay[j];
      l += d[j] > 0.0 ? d[j] + std::log((1.0 - pi) * e[j] + pi) : std::log(1.0 - pi + pi * e[j]);
    }
    return weight * l + prior_weight * (prior * std::log(at_mean) + (1.0 - prior) * std::log1p(-at_mean));
  };
  auto set_rate = [&](double v, std::vector<double>& decay) {  // ln(λ s̄) = v (−inf: λ = 0); returns λ
    const double rate = std::isinf(v) ? 0.0 : std::exp(v) / scale;
    decay.resize(s.size());
    for (std::size_t j = 0; j < s.size(); ++j) decay[j] = std::exp(-rate * s[j]);
    return rate;
  };
  std::vector<double> decay;
  auto objective = [&](double u, double v) {
    const double rate = set_rate(v, decay);
    return at_decay(u, rate, decay);
  };
  const double u_lo = std::log(1e-6 / (1.0 - 1e-6)), u_hi = -u_lo, v_lo = std::log(1e-3),
               v_hi = std::log(1e2);
  constexpr int kU = 40, kV = 40;
  auto v_at = [&](int b) {  // column b of the grid: λ = 0, then kV rates
    return b == 0 ? -std::numeric_limits<double>::infinity() : v_lo + (v_hi - v_lo) * (b - 1) / (kV - 1);
  };
  // The grid's columns in parallel (oneTBB, kernels/core/parallel.hpp), each its best row; the
  // columns' bests are then compared in order, so the answer does not depend on the threads.
  std::vector<double> column_best(kV + 1, -std::numeric_limits<double>::infinity()), column_u(kV + 1, u_lo);
  parallel_for_range(kV + 1, 1, [&](std::size_t first, std::size_t last) {
    std::vector<double> own;
    for (std::size_t b = first; b < last; ++b) {
      const double rate = set_rate(v_at(static_cast<int>(b)), own);
      for (int a = 0; a < kU; ++a) {
        const double u = u_lo + (u_hi - u_lo) * a / (kU - 1);
        if (const double l = at_decay(u, rate, own); l > column_best[b]) column_best[b] = l, column_u[b] = u;
      }
    }
  });
  double bu = u_lo, bv = -std::numeric_limits<double>::infinity(),
         bl = -std::numeric_limits<double>::infinity();
  for (int b = 0; b <= kV; ++b)
    if (column_best[b] > bl) bl = column_best[b], bu = column_u[b], bv = v_at(b);
  // Coordinate golden sections, each over one grid step either side of the current point (λ = 0
  // stays 0 unless the grid's smallest rate does better).
  const double du = (u_hi - u_lo) / (kU - 1), dv = (v_hi - v_lo) / (kV - 1);
  auto golden = [&](double lo, double hi, auto&& f) {
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
    for (int step = 0; step < 40; ++step) {
      if (f1 >= f2) {
        hi = x2, x2 = x1, f2 = f1;
        x1 = hi - g * (hi - lo), f1 = f(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2;
        x2 = lo + g * (hi - lo), f2 = f(x2);
      }
    }
    return 0.5 * (lo + hi);
  };
  for (int round = 0; round < 8; ++round) {
    const double rate = set_rate(bv, decay);
    const double u = golden(std::max(u_lo, bu - du), std::min(u_hi, bu + du),
                            [&](double x) { return at_decay(x, rate, decay); });
    if (const double l = at_decay(u, rate, decay); l >= bl) bl = l, bu = u;
    if (!std::isinf(bv)) {
      const double v = golden(std::max(v_lo, bv - dv), std::min(v_hi, bv + dv),
                              [&](double y) { return objective(bu, y); });
      if (const double l = objective(bu, v); l >= bl) bl = l, bv = v;
    }
  }
  best.constant = logistic(bu);
  best.rate = std::isinf(bv) ? 0.0 : std::exp(bv) / scale;
  return best;
}

}  // namespace trackassoc
