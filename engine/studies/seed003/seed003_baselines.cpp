// Classical seed 003 baselines (see seed003_baselines.hpp).
#include "engine/studies/seed003/seed003_baselines.hpp"

#include <cmath>
#include <limits>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {
namespace {

struct Plot {
  double x, y, pxx, pxy, pyy;  // position and converted-measurement covariance
};

Plot plot(const TrackSequences& tr, int64_t i, const RadarErrorModel& radar) {
  const double dx = tr.x[i] - radar.x, dy = tr.y[i] - radar.y;
  const double r = std::hypot(dx, dy), th = std::atan2(dy, dx);
  const double c = std::cos(th), s = std::sin(th);
  const double vr = radar.sigma_range * radar.sigma_range,
               vt = radar.sigma_bearing * radar.sigma_bearing * r * r;
  // J·diag(σr², σθ²)·Jᵀ with J = [[c, −r s], [s, r c]].
  return {tr.x[i], tr.y[i], c * c * vr + s * s * vt, c * s * (vr - vt), s * s * vr + c * c * vt};
}

// Radar-1 track k aligned to time t: interpolation weight and the two plots used.
Plot align(const TrackSequences& tr, int32_t k, double t, const RadarErrorModel& radar) {
  const int64_t a = tr.offset[k], b = tr.offset[k + 1];
  if (b - a == 1) return plot(tr, a, radar);
  int64_t i = a;
  while (i + 2 < b && tr.t[i + 1] < t) ++i;                      // bracketing (or last two) plots i, i+1
  const double w = (tr.t[i + 1] - t) / (tr.t[i + 1] - tr.t[i]);  // weight of plot i
  const Plot p = plot(tr, i, radar), q = plot(tr, i + 1, radar);
  return {w * p.x + (1 - w) * q.x, w * p.y + (1 - w) * q.y, w * w * p.pxx + (1 - w) * (1 - w) * q.pxx,
          w * w * p.pxy + (1 - w) * (1 - w) * q.pxy, w * w * p.pyy + (1 - w) * (1 - w) * q.pyy};
}

double lambda(const TrackSequences& r1, int32_t i, const TrackSequences& r2, int32_t j,
              const ClassicalBaselineOptions& o) {
  const int64_t last = r2.offset[j + 1] - 1;
  const Plot z = plot(r2, last, o.radar2);
  const Plot a = align(r1, i, r2.t[last], o.radar1);
  const double dx = z.x - a.x, dy = z.y - a.y;
  const double cxx = z.pxx + a.pxx, cxy = z.pxy + a.pxy, cyy = z.pyy + a.pyy;
  const double det = cxx * cyy - cxy * cxy;
  return (cyy * dx * dx - 2 * cxy * dx * dy + cxx * dy * dy) / det;
}

double distance(const TrackSequences& r1, int32_t i, const TrackSequences& r2, int32_t j,
                const ClassicalBaselineOptions& o) {
  const int64_t last = r2.offset[j + 1] - 1;
  const Plot a = align(r1, i, r2.t[last], o.radar1);
  return std::hypot(r2.x[last] - a.x, r2.y[last] - a.y);
}

}  // namespace

void ClassicalBaselineOptions::validate() const {
  require(gate_probability > 0 && gate_probability < 1, "ClassicalBaselineOptions.gate_probability",
          "must be in (0, 1)");
  require(nn_gate > 0, "ClassicalBaselineOptions.nn_gate", "must be > 0");
  for (const RadarErrorModel* r : {&radar1, &radar2})
    require(r->sigma_range > 0 && r->sigma_bearing > 0, "ClassicalBaselineOptions.radar",
            "sigmas must be > 0");
}

std::vector<double> weighted_statistic_matrix(const TrackSequences& r1, const TrackSequences& r2,
                                              const ClassicalBaselineOptions& o) {
  o.validate();
  const int32_t n1 = r1.size(), n2 = r2.size();
  std::vector<double> out(static_cast<std::size_t>(n1) * n2);
  parallel_for_range(static_cast<std::size_t>(n1), 4, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (int32_t j = 0; j < n2; ++j) out[i * n2 + j] = lambda(r1, static_cast<int32_t>(i), r2, j, o);
  });
  return out;
}

std::vector<double> weighted_statistic_pairs(const TrackSequences& r1, const TrackSequences& r2,
                                             const PairSet& pairs, const ClassicalBaselineOptions& o) {
  o.validate();
  std::vector<double> out(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) out[k] = lambda(r1, pairs.left[k], r2, pairs.right[k], o);
  return out;
}

std::vector<int32_t> associate_weighted_test(const TrackSequences& r1, const TrackSequences& r2,
                                             const ClassicalBaselineOptions& o) {
  const int32_t n1 = r1.size(), n2 = r2.size();
  std::vector<double> cost = weighted_statistic_matrix(r1, r2, o);
  const double gate = chi_square_quantile(o.gate_probability, 2);
  // Cost λ − gate ≤ 0 for gated pairs, so assigning a gated pair never loses to leaving it out.
  for (double& c : cost) c = c <= gate ? c - gate : std::numeric_limits<double>::infinity();
  std::vector<int32_t> out(static_cast<std::size_t>(n1), -1);
  if (n1 == 0 || n2 == 0) return out;
  LapOptions lo;
  lo.allow_unassigned = true;
  const LapResult lap = solve_lap(cost, n1, n2, lo);
  for (int32_t i = 0; i < n1; ++i) {
    const int32_t j = lap.row_to_col[i];
    if (j >= 0 && std::isfinite(cost[static_cast<std::size_t>(i) * n2 + j])) out[i] = j;
  }
  return out;
}

std::vector<int32_t> associate_nearest_neighbour(const TrackSequences& r1, const TrackSequences& r2,
                                                 const ClassicalBaselineOptions& o) {
  o.validate();
  const int32_t n1 = r1.size(), n2 = r2.size();
  std::vector<int32_t> out(static_cast<std::size_t>(n1), -1);
  for (int32_t i = 0; i < n1; ++i) {
    double best = o.nn_gate;
    for (int32_t j = 0; j < n2; ++j) {
      const double d = distance(r1, i, r2, j, o);
      if (d < best) best = d, out[i] = j;
    }
  }
  return out;
}

}  // namespace trackassoc
