#include "kernels/filters/cs_parallel.hpp"

#include <cmath>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/filters/cs_block.hpp"

namespace trackassoc {

void CsParallelOptions::validate() const {
  try {
    f1.validate();
  } catch (const InputError& e) {
    throw InputError(std::string("CsParallelOptions.f1: ") + e.what());
  }
  try {
    f2.validate();
  } catch (const InputError& e) {
    throw InputError(std::string("CsParallelOptions.f2: ") + e.what());
  }
  require(grain_blocks >= 1, "CsParallelOptions.grain_blocks", "expected ≥ 1");
}

namespace {

template <int d>
void parallel_blocks(CsParallelBank& bank, const block::CsContext& c1, const block::CsContext& c2,
                     const PositionScan& scan, bool predict, const InnovationOutput& out, std::size_t b0,
                     std::size_t b1) {
  using block::W;
  constexpr int D = 3 * d;
  const bool want = !out.nis.empty() || !out.log_likelihood.empty();
  block::LaneMeasurement<d> m;
  block::LaneInnovation v;
  double one[W], zero[W], prev[W], y[W], q1[d][6][W], q2[d][6][W];
  for (int l = 0; l < W; ++l) one[l] = 1.0, zero[l] = 0.0;
  for (std::size_t b = b0; b < b1; ++b) {
    double* x1 = bank.f1.block(b);
    double* x2 = bank.f2.block(b);
    block::load_measurement<d>(scan, b, bank.size(), m);
    if (predict) {
      for (int l = 0; l < W; ++l) {
        const std::size_t i = b * W + l;
        prev[l] = i < bank.size() ? bank.scale[i] : 1.0;
      }
      block::cs_predict<d>(x1, c1, one, q1);
      block::cs_predict<d>(x2, c2, zero, q2);  // Φ P Φᵀ only; Q2 is added once y is known
      const double* p1 = x1 + D * W;
      const double* p2 = x2 + D * W;
      for (int l = 0; l < W; ++l) {
        double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
        for (int o = 0; o < 3; ++o)
          for (int a = 0; a < d; ++a) {
            const int c = o * d + a, k = block::pidx(D, c, c);
            const double diff = x1[c * W + l] - x2[c * W + l];
            num[o] += diff * diff;
            // F2's covariance at the noise scale in force (prev); position adds R (seed 002 Eq. 3's s).
            den[o] += p1[k * W + l] + p2[k * W + l] + prev[l] * q2[a][block::pidx(3, o, o)][l];
            if (o == 0) den[o] += 2.0 * m.detected[l] * m.R[block::pidx(d, a, a)][l];
          }
        const auto u = cs_network_inputs(num[0] / den[0], num[1] / den[1], num[2] / den[2]);
        y[l] = bank.network.evaluate(u);
      }
      block::add_process_noise<d>(x2, q2, y);
      for (int l = 0; l < W; ++l) {
        const std::size_t i = b * W + l;
        if (i < bank.size()) bank.scale[i] = y[l];
      }
    }
    block::update<d, 3>(x1, m, nullptr);
    block::update<d, 3>(x2, m, want ? &v : nullptr);
    if (want) block::store_innovation(out, b, bank.size(), v);
  }
}

}  // namespace

FilterStepSummary cs_parallel_step(CsParallelBank& bank, double dt, const PositionScan& scan,
                                   const CsParallelOptions& o, InnovationOutput out) {
  o.validate();
  require(std::isfinite(dt) && dt >= 0.0, "cs_parallel_step.dt", "expected a finite scan interval ≥ 0");
  block::check_scan(scan, out, bank.size(), bank.f2.spatial_dim(), "cs_parallel_step.scan");
  const block::CsContext c1(o.f1, dt), c2(o.f2, dt);
  parallel_for_range(bank.f2.num_blocks(), o.grain_blocks, [&](std::size_t b0, std::size_t b1) {
    if (bank.f2.spatial_dim() == 2)
      parallel_blocks<2>(bank, c1, c2, scan, dt != 0.0, out, b0, b1);
    else
      parallel_blocks<3>(bank, c1, c2, scan, dt != 0.0, out, b0, b1);
  });
  FilterStepSummary s;
  s.tracks = bank.size();
  s.updated = scan.detected.empty() ? bank.size() : 0;
  for (uint8_t f : scan.detected) s.updated += f != 0;
  return s;
}

}  // namespace trackassoc
