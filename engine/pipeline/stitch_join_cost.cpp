// The join cost of fragment stitching; see engine/pipeline/stitch_join_cost.hpp.
#include "engine/pipeline/stitch_join_cost.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "kernels/core/parallel.hpp"

namespace trackassoc {
namespace {

// Fixed capacity (D ≤ 6): no heap allocation per candidate.
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

// Row r's state and covariance predicted by dt (either sign) with CV and Q(|dt|) of q = σ_a²;
// Q's cross term follows F's direction (Bar-Shalom, Li, Kirubarajan 2001 §6.2.2).
void predict(const TrackTable& t, std::size_t r, double dt, double q, Vector& x, Matrix& P) {
  const int D = t.dim(), d = D / 2;
  const double a = std::fabs(dt), sgn = dt < 0 ? -1.0 : 1.0;
  Matrix F = Matrix::Identity(D, D), Q = Matrix::Zero(D, D), P0(D, D);
  for (int i = 0; i < d; ++i) {
    F(i, d + i) = dt;
    Q(i, i) = q * a * a * a / 3.0;
    Q(i, d + i) = Q(d + i, i) = sgn * q * a * a / 2.0;
    Q(d + i, d + i) = q * a;
  }
  Vector x0(D);
  for (int i = 0; i < D; ++i) x0[i] = t.state[i][r];
  for (int i = 0, k = 0; i < D; ++i)
    for (int j = i; j < D; ++j, ++k) P0(i, j) = P0(j, i) = t.cov[k][r];
  x = F * x0;
  P = F * P0 * F.transpose() + Q;
}

// ln N_turn − ln N_quiet, kept finite (±10⁴ nats: responsibilities of 0 or 1 all the same), as
// join_cost's `turn_log_ratio`, learn_quiet_sigma's d and the revision's ratio all are.
double clamped_log_ratio(double l_turn, double l_quiet) { return std::clamp(l_turn - l_quiet, -1e4, 1e4); }

}  // namespace

// ln(e^a + e^b) without overflow.
double log_sum_exp(double a, double b) {
  const double m = std::max(a, b);
  return m == -std::numeric_limits<double>::infinity() ? m : m + std::log(std::exp(a - m) + std::exp(b - m));
}

double predicted_log_det(const TrackTable& t, std::size_t r, double dt, double q) {
  Vector x;
  Matrix P;
  predict(t, r, dt, q, x, P);
  return Eigen::LDLT<Matrix>(P).vectorD().array().log().sum();
}

GapStatistic gap_statistic(const TrackTable& t, std::size_t end, std::size_t start, double q) {
  const int D = t.dim();
  const double tm = 0.5 * (t.t[end] + t.t[start]);
  Vector x1, x2;
  Matrix P1, P2;
  predict(t, end, tm - t.t[end], q, x1, P1);
  predict(t, start, tm - t.t[start], q, x2, P2);
  const Vector e = x1 - x2;
  const Eigen::LDLT<Matrix> S(P1 + P2);
  GapStatistic g;
  g.m2 = e.dot(S.solve(e));
  g.log_det = D * std::log(2.0 * std::numbers::pi);
  for (int i = 0; i < D; ++i) g.log_det += std::log(S.vectorD()[i]);
  return g;
}

// A conservative pre-gate without a factorisation: the position part's m² is at most the full
// m² (a marginal's Mahalanobis form never exceeds the joint one) and at least |e_p|²/trace(S_pp),
// so |e_p|² > gate·trace(S_pp) means m² > gate. Far pairs (most of them in a wide scene) are
// refused from the diagonal alone; the joins are exactly those without it.
bool gap_surely_outside(const TrackTable& t, std::size_t end, std::size_t start, double q, double gate) {
  const int D = t.dim(), d = D / 2;
  auto packed = [D](int r, int c) { return r * D - r * (r - 1) / 2 + (c - r); };  // r ≤ c
  const double tm = 0.5 * (t.t[end] + t.t[start]);
  double e2 = 0.0, trace = 0.0;
  for (int i = 0; i < d; ++i) {
    double e = 0.0;
    for (const auto& [r, sign] : {std::pair{end, 1.0}, std::pair{start, -1.0}}) {
      const double dt = tm - t.t[r], a = std::fabs(dt);
      e += sign * (t.state[i][r] + dt * t.state[d + i][r]);
      trace += t.cov[packed(i, i)][r] + 2.0 * dt * t.cov[packed(i, d + i)][r] +
               dt * dt * t.cov[packed(d + i, d + i)][r] + q * a * a * a / 3.0;
    }
    e2 += e * e;
  }
  return e2 > gate * trace;
}

double join_cost(const TrackTable& t, std::size_t end, std::size_t start, const TrackStitchOptions& o,
                 double gate, double* turn_log_ratio) {
  if (gap_surely_outside(t, end, start, o.turn_sigma * o.turn_sigma, gate))
    return std::numeric_limits<double>::infinity();
  const GapStatistic turn = gap_statistic(t, end, start, o.turn_sigma * o.turn_sigma);
  if (!(turn.m2 <= gate)) return std::numeric_limits<double>::infinity();
  const GapStatistic quiet = gap_statistic(t, end, start, o.manoeuvre_sigma * o.manoeuvre_sigma);
  if (turn_log_ratio) *turn_log_ratio = clamped_log_ratio(turn.log_density(), quiet.log_density());
  const double minus_inf = -std::numeric_limits<double>::infinity();
  const double l_quiet =
      o.turn_probability < 1.0 ? std::log1p(-o.turn_probability) + quiet.log_density() : minus_inf;
  const double l_turn =
      o.turn_probability > 0.0 ? std::log(o.turn_probability) + turn.log_density() : minus_inf;
  return -log_sum_exp(l_quiet, l_turn);
}

JoinCostRevision::JoinCostRevision(const TrackStitchOptions& o, double sigma)
    : quiet_was_(std::log1p(-o.turn_probability)),
      turn_was_(std::log(o.turn_probability)),
      q_was_(o.manoeuvre_sigma * o.manoeuvre_sigma),
      q_now_(sigma * sigma),
      q_turn_(o.turn_sigma * o.turn_sigma) {}

double JoinCostRevision::operator()(const TrackTable& t, std::size_t end, std::size_t start,
                                    double turn_weight, float& turn_log_ratio) const {
  if (q_now_ == q_was_)
    return log_sum_exp(quiet_was_, turn_was_ + turn_log_ratio) -
           log_sum_exp(std::log1p(-turn_weight), std::log(turn_weight) + turn_log_ratio);
  // The quiet density changes too: −ln p(e) = −ln[(1 − π) N_quiet + π N_turn] replaced whole.
  auto log_density = [&](double q) { return gap_statistic(t, end, start, q).log_density(); };
  const double l_was = log_density(q_was_), l_now = log_density(q_now_), l_turn = log_density(q_turn_);
  turn_log_ratio = static_cast<float>(clamped_log_ratio(l_turn, l_now));
  return log_sum_exp(quiet_was_ + l_was, turn_was_ + l_turn) -
         log_sum_exp(std::log1p(-turn_weight) + l_now, std::log(turn_weight) + l_turn);
}

QuietModelFit learn_quiet_sigma(const TrackTable& t, std::span<const JoinRows> joins,
                                std::span<const float> spans, const TrackStitchOptions& o) {
  const std::size_t J = joins.size();
  // ln N(e_j; 0, S) under q = σ_a², each join's statistic once per σ_a.
  auto log_density = [&](double q, std::vector<double>& out) {
    out.resize(J);
    parallel_for_range(J, 256, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t j = lo; j < hi; ++j)
        out[j] = gap_statistic(t, joins[j].end, joins[j].start, q).log_density();
    });
  };
  std::vector<double> l_turn, l_quiet;
  log_density(o.turn_sigma * o.turn_sigma, l_turn);
  std::vector<float> d(J);
  QuietModelFit best;
  double best_score = -std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 8; ++k) {
    const double sigma = o.manoeuvre_sigma * std::exp2(k / 4.0);
    if (k > 0 && sigma > o.turn_sigma) break;  // the quiet model stays the sharper one
    log_density(sigma * sigma, l_quiet);
    for (std::size_t j = 0; j < J; ++j)  // as join_cost's turn_log_ratio
      d[j] = static_cast<float>(clamped_log_ratio(l_turn[j], l_quiet[j]));
    const SpanMixtureWeight w = span_mixture_weight(d, spans, o.turn_probability, o.turn_prior_joins);
    const double z = std::log(sigma / o.quiet_sigma_prior) / o.quiet_sigma_prior_sd;
    double score = -0.5 * z * z;
    for (std::size_t j = 0; j < J; ++j) {
      const double p = std::min(w.at(spans[j]), 1.0 - 1e-16);
      score += log_sum_exp(std::log1p(-p) + l_quiet[j], std::log(p) + l_turn[j]);
    }
    if (k > 0 && !(score > best_score)) break;  // past the first maximum (the floor's kept whatever)
    best_score = score, best = {sigma, w};
  }
  return best;
}

}  // namespace trackassoc
