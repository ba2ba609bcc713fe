#include "kernels/learning/bp_network.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

namespace {
double logistic(double z) { return 1.0 / (1.0 + std::exp(-z)); }

double total_error(const BpNetwork& net, const std::vector<BpSample>& samples) {
  double e = 0.0;
  for (const auto& s : samples) {
    const double r = net.evaluate(s.input) - s.target;
    e += 0.5 * r * r;
  }
  return e;
}
}  // namespace

double BpNetwork::evaluate(const std::array<double, kInputs>& x) const {
  double z = w2[kHidden];
  for (int h = 0; h < kHidden; ++h) {
    double a = w1[h][kInputs];
    for (int i = 0; i < kInputs; ++i) a += w1[h][i] * x[i];
    z += w2[h] * logistic(a);
  }
  return logistic(z);
}

void BpTrainingOptions::validate() const {
  require(std::isfinite(learning_rate) && learning_rate > 0.0, "BpTrainingOptions.learning_rate",
          "expected > 0");
  require(std::isfinite(momentum) && momentum >= 0.0 && momentum < 1.0, "BpTrainingOptions.momentum",
          "expected in [0, 1)");
  require(iterations >= 0 && iterations <= 100000000, "BpTrainingOptions.iterations", "expected in [0, 1e8]");
}

BpTrainingSummary train_bp_network(BpNetwork& net, const std::vector<BpSample>& samples,
                                   const BpTrainingOptions& o) {
  o.validate();
  require(!samples.empty(), "train_bp_network.samples", "expected at least one training pair");
  const auto start = std::chrono::steady_clock::now();
  constexpr int I = BpNetwork::kInputs, H = BpNetwork::kHidden;
  CounterRng rng(o.seed);
  for (auto& row : net.w1)
    for (auto& w : row) w = rng.uniform(-0.5, 0.5);
  for (auto& w : net.w2) w = rng.uniform(-0.5, 0.5);
  BpTrainingSummary summary;
  summary.initial_error = total_error(net, samples);
  std::array<std::array<double, I + 1>, H> dw1{};
  std::array<double, H + 1> dw2{};
  for (int it = 0; it < o.iterations; ++it) {
    for (const auto& s : samples) {
      // Forward.
      double hidden[H];
      double z = net.w2[H];
      for (int h = 0; h < H; ++h) {
        double a = net.w1[h][I];
        for (int i = 0; i < I; ++i) a += net.w1[h][i] * s.input[i];
        hidden[h] = logistic(a);
        z += net.w2[h] * hidden[h];
      }
      const double y = logistic(z);
      // Backward: δ_out = (t − y)·y(1 − y); δ_h = δ_out·w2_h·h(1 − h).
      const double delta_out = (s.target - y) * y * (1.0 - y);
      for (int h = 0; h < H; ++h) {
        const double delta_h = delta_out * net.w2[h] * hidden[h] * (1.0 - hidden[h]);
        for (int i = 0; i <= I; ++i) {
          const double xi = i < I ? s.input[i] : 1.0;
          dw1[h][i] = o.learning_rate * delta_h * xi + o.momentum * dw1[h][i];
          net.w1[h][i] += dw1[h][i];
        }
      }
      for (int h = 0; h <= H; ++h) {
        const double xh = h < H ? hidden[h] : 1.0;
        dw2[h] = o.learning_rate * delta_out * xh + o.momentum * dw2[h];
        net.w2[h] += dw2[h];
      }
    }
  }
  summary.iterations = o.iterations;
  summary.final_error = total_error(net, samples);
  summary.final_mse = 2.0 * summary.final_error / static_cast<double>(samples.size());
  summary.wall_time_s = seconds_since(start);
  return summary;
}

std::array<double, 3> cs_network_inputs(double u1, double u2, double u3) {
  auto squash = [](double u) { return std::isfinite(u) ? (u < 0.0 ? 0.0 : u / (1.0 + u)) : 1.0; };
  return {squash(u1), squash(u2), squash(u3)};
}

std::vector<BpSample> cs_network_training_set() {
  constexpr double y_min = 0.05;
  const double levels[8] = {0.0, 0.1, 0.3, 0.6, 1.0, 2.0, 4.0, 10.0};
  std::vector<BpSample> out;
  for (double u : levels) {
    const double target = y_min + (1.0 - y_min) * u / (u + 1.0);
    out.push_back({cs_network_inputs(u, u, u), target});
    out.push_back({cs_network_inputs(0.5 * u, u, 1.5 * u), target});
  }
  return out;
}

BpNetwork trained_cs_network(BpTrainingSummary* summary) {
  BpNetwork net;
  const BpTrainingSummary s = train_bp_network(net, cs_network_training_set(), BpTrainingOptions{});
  if (summary) *summary = s;
  return net;
}

}  // namespace trackassoc
