#include "kernels/fuzzy/fuzzy_association.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "kernels/core/error.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

double gaussian_membership(double u, double u_max) {
  const double r = u / u_max;
  return std::exp(-r * r);  // seed 001 Eq. 5
}

void SynthesisOptions::validate(std::size_t n) const {
  const std::string w = "SynthesisOptions.";
  require(std::isfinite(q) && q > 0.0, w + "q", "expected q > 0, got " + std::to_string(q));
  if (function == SynthesisFunction::kWeightedMean || function == SynthesisFunction::kWeightedPowerMean) {
    require(weights.size() == n, w + "weights",
            "expected " + std::to_string(n) + " weights, got " + std::to_string(weights.size()));
    double sum = 0.0;
    for (double a : weights) {
      require(std::isfinite(a) && a >= 0.0 && a <= 1.0, w + "weights", "each weight must be in [0, 1]");
      sum += a;
    }
    require(std::abs(sum - 1.0) < 1e-9, w + "weights",
            "must sum to 1 (Eq. 11), sum is " + std::to_string(sum));
  }
}

double synthesise(std::span<const double> d, const SynthesisOptions& o) {
  const std::size_t n = d.size();
  if (n == 0) return 0.0;
  switch (o.function) {
    case SynthesisFunction::kPowerMean: {  // Eq. 9
      double s = 0.0;
      for (double v : d) s += std::pow(v, o.q);
      return std::pow(s / static_cast<double>(n), 1.0 / o.q);
    }
    case SynthesisFunction::kGeometricMean: {  // Eq. 10
      double p = 1.0;
      for (double v : d) p *= v;
      return std::pow(p, 1.0 / static_cast<double>(n));
    }
    case SynthesisFunction::kWeightedMean: {  // Eq. 11
      double s = 0.0;
      for (std::size_t l = 0; l < n; ++l) s += o.weights[l] * d[l];
      return s;
    }
    case SynthesisFunction::kWeightedPowerMean: {  // Eq. 12
      double s = 0.0;
      for (std::size_t l = 0; l < n; ++l) s += o.weights[l] * std::pow(d[l], o.q);
      return std::pow(s, 1.0 / o.q);
    }
    case SynthesisFunction::kMinMaxMean: {  // Eq. 13
      const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
      return 0.5 * (*lo + *hi);
    }
  }
  return 0.0;
}

std::vector<double> normalise_reliabilities(std::span<const double> w) {
  require(!w.empty(), "reliability", "expected at least one sensor");
  double mx = 0.0;
  for (double v : w) {
    require(std::isfinite(v) && v >= 0.0, "reliability",
            "expected finite values >= 0, got " + std::to_string(v));
    mx = std::max(mx, v);
  }
  require(mx > 0.0, "reliability", "at least one sensor must have a reliability > 0");
  std::vector<double> out(w.begin(), w.end());
  for (double& v : out) v /= mx;  // seed 001 Eq. 1
  return out;
}

double heading_difference(double a, double b) {
  double d = std::fmod(std::abs(a - b), 2.0 * std::numbers::pi);
  return d > std::numbers::pi ? 2.0 * std::numbers::pi - d : d;
}

FuzzyFactors fuzzy_factors(const PlanarState& a, const PlanarState& b) {
  FuzzyFactors u;
  u.position = std::hypot(a.x - b.x, a.y - b.y);                                   // Eq. 2
  u.speed = std::abs(std::hypot(a.vx, a.vy) - std::hypot(b.vx, b.vy));             // Eq. 3, speeds (erratum)
  u.heading = heading_difference(std::atan2(a.vy, a.vx), std::atan2(b.vy, b.vx));  // Eq. 4, atan2 (erratum)
  return u;
}

void FactorScales::validate() const {
  require(std::isfinite(position) && position > 0, "FactorScales.position", "u_max must be > 0");
  require(std::isfinite(speed) && speed > 0, "FactorScales.speed", "u_max must be > 0");
  require(std::isfinite(heading) && heading > 0, "FactorScales.heading", "u_max must be > 0");
}

std::array<double, 3> fuzzy_memberships(const FuzzyFactors& u, const FactorScales& s) {
  return {gaussian_membership(u.position, s.position), gaussian_membership(u.speed, s.speed),
          gaussian_membership(u.heading, s.heading)};
}

void validate_packets(const PacketSpans& p, std::size_t num_sensors, std::size_t num_local) {
  const std::size_t n = p.size();
  require(p.sensor.size() == n && p.local.size() == n && p.x.size() == n && p.y.size() == n, "packets",
          "columns sensor, local, t, x, y must have the same length");
  for (std::size_t i = 0; i < n; ++i) {
    require(std::isfinite(p.t[i]) && std::isfinite(p.x[i]) && std::isfinite(p.y[i]), "packets",
            "row " + std::to_string(i) + ": t, x and y must be finite");
    require(p.sensor[i] >= 0 && static_cast<std::size_t>(p.sensor[i]) < num_sensors, "packets",
            "row " + std::to_string(i) + ": sensor index out of range");
    require(p.local[i] >= 0 && static_cast<std::size_t>(p.local[i]) < num_local, "packets",
            "row " + std::to_string(i) + ": local track index out of range");
  }
}

std::vector<std::size_t> arrival_order(std::span<const double> t) {
  std::vector<std::size_t> order(t.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return t[a] < t[b]; });
  return order;
}

void FusionOutput::resize(std::size_t n) {
  system_track.assign(n, -1);
  for (auto* c : {&x, &y, &vx, &vy, &degree}) c->assign(n, std::numeric_limits<double>::quiet_NaN());
}

AlphaBetaOptions FuzzyAssociationOptions::default_smoother() {
  AlphaBetaOptions o;
  o.gains = AlphaBetaGainMode::kKalata;
  o.process_noise = 2.0;
  o.measurement_noise = 150.0;
  return o;
}

void FuzzyAssociationOptions::validate() const {
  scales.validate();
  synthesis.validate(3);
  require(std::isfinite(gate) && gate > 0, "FuzzyAssociationOptions.gate", "expected a gate radius > 0 [m]");
  require(std::isfinite(min_degree) && min_degree >= 0 && min_degree <= 1,
          "FuzzyAssociationOptions.min_degree", "expected a value in [0, 1]");
  require(std::isfinite(track_timeout) && track_timeout >= 0, "FuzzyAssociationOptions.track_timeout",
          "expected >= 0 [s] (0 = never)");
  smoother.validate();
}

FuzzyAssociator::FuzzyAssociator(const FuzzyAssociationOptions& options,
                                 std::span<const double> reliabilities, std::size_t num_local)
    : options_(options), reliability_(normalise_reliabilities(reliabilities)), bank_(2, 0, options.smoother) {
  options_.validate();
  last_t_.assign(num_local, 0.0);
  last_x_.assign(num_local, 0.0);
  last_y_.assign(num_local, 0.0);
  has_last_.assign(num_local, 0);
}

FuzzyAssociator::Decision FuzzyAssociator::process(int32_t sensor, int32_t local, double t, double x,
                                                   double y) {
  Decision d;
  const bool first = !has_last_[local];
  const double dt = t - last_t_[local];
  const double px = last_x_[local], py = last_y_[local];
  has_last_[local] = 1;
  last_t_[local] = t;
  last_x_[local] = x;
  last_y_[local] = y;
  // No temporary track from a first plot, nor from two plots at one time (no direction).
  if (first || !(dt > 0.0)) return d;

  // The temporary track (seed 001 §2).
  const PlanarState temp{x, y, (x - px) / dt, (y - py) / dt};
  const double w_temp = reliability_[sensor];
  const bool weigh_temp = options_.weighting == ReliabilityWeighting::kTemporaryTrack ||
                          options_.weighting == ReliabilityWeighting::kProduct;
  const bool weigh_sys = options_.weighting == ReliabilityWeighting::kSystemTrack ||
                         options_.weighting == ReliabilityWeighting::kProduct;

  int32_t best = -1;
  double best_mu = -1.0;
  const std::size_t J = num_system_tracks();
  const double* sx = bank_.position[0].data();
  const double* sy = bank_.position[1].data();
  const double* svx = bank_.velocity[0].data();
  const double* svy = bank_.velocity[1].data();
  for (std::size_t j = 0; j < J; ++j) {
    const double age = t - last_time_[j];
    if (options_.track_timeout > 0.0 && age > options_.track_timeout) continue;
    const PlanarState sys{sx[j] + svx[j] * age, sy[j] + svy[j] * age, svx[j], svy[j]};
    const double u1 = std::hypot(temp.x - sys.x, temp.y - sys.y);
    if (u1 > options_.gate) continue;  // outside the tracking gate
    const FuzzyFactors u = fuzzy_factors(temp, sys);
    const auto m = fuzzy_memberships(u, options_.scales);
    double mu = synthesise(m, options_.synthesis);  // seed 001 Eq. 11 (or 9, 10, 12, 13)
    if (weigh_temp) mu *= w_temp;                   // Eq. 16
    if (weigh_sys) mu *= system_reliability_[j];
    if (mu < options_.min_degree) continue;
    if (mu > best_mu) {  // ties: the older system track
      best_mu = mu;
      best = static_cast<int32_t>(j);
    }
  }
  ++decisions_;
  if (best < 0) {  // starts a new system track
    const double pos[2] = {temp.x, temp.y}, vel[2] = {temp.vx, temp.vy};
    best = static_cast<int32_t>(bank_.add_track(pos, vel));
    last_time_.push_back(t);
    system_reliability_.push_back(w_temp);
    d.new_track = true;
  } else {  // alpha-beta smoothing of the system track with the temporary track's position
    bank_.predict_track(best, t - last_time_[best]);
    const double z[2] = {temp.x, temp.y};
    bank_.update_track(best, z);
    last_time_[best] = t;
    system_reliability_[best] = w_temp;  // the reliability of the latest packet (§2)
    d.degree = best_mu;
  }
  d.system_track = best;
  d.fused = {bank_.position[0][best], bank_.position[1][best], bank_.velocity[0][best],
             bank_.velocity[1][best]};
  return d;
}

FusionOutput run_fuzzy_association(const PacketSpans& packets, std::span<const double> reliabilities,
                                   std::size_t num_local, const FuzzyAssociationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.validate();
  validate_packets(packets, reliabilities.size(), num_local);
  FuzzyAssociator fc(options, reliabilities, num_local);
  FusionOutput out;
  out.resize(packets.size());
  for (std::size_t i : arrival_order(packets.t)) {
    const auto d = fc.process(packets.sensor[i], packets.local[i], packets.t[i], packets.x[i], packets.y[i]);
    if (d.system_track < 0) continue;
    out.system_track[i] = d.system_track;
    out.x[i] = d.fused.x;
    out.y[i] = d.fused.y;
    out.vx[i] = d.fused.vx;
    out.vy[i] = d.fused.vy;
    if (!d.new_track) out.degree[i] = d.degree;
  }
  out.num_system_tracks = static_cast<int32_t>(fc.num_system_tracks());
  out.summary.termination = Termination::kHeuristic;
  out.summary.feasible = true;
  out.summary.iterations = fc.decisions();
  out.summary.wall_time_s = seconds_since(start);
  out.summary.message = std::to_string(fc.decisions()) + " temporary tracks, " +
                        std::to_string(fc.num_system_tracks()) + " system tracks";
  return out;
}

}  // namespace trackassoc
