#include "kernels/filters/cs_filter.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/filters/cs_block.hpp"

namespace trackassoc {

void CsOptions::validate() const {
  require(std::isfinite(manoeuvre_frequency) && manoeuvre_frequency > 0.0, "CsOptions.manoeuvre_frequency",
          "expected α > 0 [1/s], got " + std::to_string(manoeuvre_frequency));
  require(std::isfinite(a_max) && a_max > 0.0, "CsOptions.a_max",
          "expected > 0 [m/s²], got " + std::to_string(a_max));
  require(std::isfinite(a_neg_max) && a_neg_max < 0.0, "CsOptions.a_neg_max",
          "expected < 0 [m/s²], got " + std::to_string(a_neg_max));
  require(std::isfinite(min_accel_variance) && min_accel_variance >= 0.0, "CsOptions.min_accel_variance",
          "expected ≥ 0");
  require(grain_blocks >= 1, "CsOptions.grain_blocks", "expected ≥ 1");
}

double cs_accel_variance(double a, const CsOptions& o) {
  constexpr double k = (4.0 - std::numbers::pi) / std::numbers::pi;
  const double gap = a >= 0.0 ? o.a_max - a : o.a_neg_max - a;  // seed 002 Eq. 2
  return std::max(o.min_accel_variance, k * gap * gap);
}

Eigen::Matrix3d cs_transition(double alpha, double T) {
  const double e = std::exp(-alpha * T);
  Eigen::Matrix3d F;
  F << 1.0, T, (alpha * T - 1.0 + e) / (alpha * alpha), 0.0, 1.0, (1.0 - e) / alpha, 0.0, 0.0, e;
  return F;
}

Eigen::Matrix3d cs_process_noise_shape(double a, double T) {
  // Singer (1970), Eq. 19; multiplied by σ_w² = 2ασ_a² by the caller.
  const double e = std::exp(-a * T), e2 = std::exp(-2.0 * a * T), aT = a * T;
  const double q11 = (1.0 - e2 + 2.0 * aT + 2.0 * aT * aT * aT / 3.0 - 2.0 * aT * aT - 4.0 * aT * e) /
                     (2.0 * std::pow(a, 5));
  const double q12 = (e2 + 1.0 - 2.0 * e + 2.0 * aT * e - 2.0 * aT + aT * aT) / (2.0 * std::pow(a, 4));
  const double q13 = (1.0 - e2 - 2.0 * aT * e) / (2.0 * std::pow(a, 3));
  const double q22 = (4.0 * e - 3.0 - e2 + 2.0 * aT) / (2.0 * std::pow(a, 3));
  const double q23 = (e2 + 1.0 - 2.0 * e) / (2.0 * a * a);
  const double q33 = (1.0 - e2) / (2.0 * a);
  Eigen::Matrix3d q;
  q << q11, q12, q13, q12, q22, q23, q13, q23, q33;
  return q;
}

namespace {

template <int d>
void cs_blocks(KinematicBank& bank, const block::CsContext& cx, const PositionScan& scan, bool predict,
               std::span<const double> scale, const InnovationOutput& out, std::size_t b0, std::size_t b1) {
  const bool want = !out.nis.empty() || !out.log_likelihood.empty();
  block::LaneMeasurement<d> m;
  block::LaneInnovation v;
  double s[block::W], q[d][6][block::W];
  for (std::size_t b = b0; b < b1; ++b) {
    double* blk = bank.block(b);
    if (predict) {
      for (int l = 0; l < block::W; ++l) {
        const std::size_t i = b * block::W + l;
        s[l] = scale.empty() || i >= bank.size() ? 1.0 : scale[i];
      }
      block::cs_predict<d>(blk, cx, s, q);
    }
    block::load_measurement<d>(scan, b, bank.size(), m);
    block::update<d, 3>(blk, m, want ? &v : nullptr);
    if (want) block::store_innovation(out, b, bank.size(), v);
  }
}

}  // namespace

FilterStepSummary cs_bank_step(KinematicBank& bank, double dt, const PositionScan& scan, const CsOptions& o,
                               std::span<const double> scale, InnovationOutput out) {
  o.validate();
  require(bank.order() == 3, "cs_bank_step.bank", "the CS model needs an order-3 (acceleration) bank");
  require(std::isfinite(dt) && dt >= 0.0, "cs_bank_step.dt", "expected a finite scan interval ≥ 0");
  require(scale.empty() || scale.size() == bank.size(), "cs_bank_step.noise_scale",
          "expected empty or one per track");
  block::check_scan(scan, out, bank.size(), bank.spatial_dim(), "cs_bank_step.scan");
  const block::CsContext cx(o, dt);
  parallel_for_range(bank.num_blocks(), o.grain_blocks, [&](std::size_t b0, std::size_t b1) {
    if (bank.spatial_dim() == 2)
      cs_blocks<2>(bank, cx, scan, dt != 0.0, scale, out, b0, b1);
    else
      cs_blocks<3>(bank, cx, scan, dt != 0.0, scale, out, b0, b1);
  });
  FilterStepSummary s;
  s.tracks = bank.size();
  s.updated = scan.detected.empty() ? bank.size() : 0;
  for (uint8_t f : scan.detected) s.updated += f != 0;
  return s;
}

}  // namespace trackassoc
