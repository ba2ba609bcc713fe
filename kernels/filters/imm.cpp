#include "kernels/filters/imm.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/filters/kalman_block.hpp"

namespace trackassoc {

void ImmOptions::validate() const {
  const std::size_t M = models.size();
  require(M >= 1, "ImmOptions.models", "expected at least one model");
  require(transition.size() == M * M, "ImmOptions.transition",
          "expected " + std::to_string(M * M) + " entries (M×M), got " + std::to_string(transition.size()));
  require(initial_probabilities.size() == M, "ImmOptions.initial_probabilities",
          "expected " + std::to_string(M) + " entries, got " + std::to_string(initial_probabilities.size()));
  for (std::size_t i = 0; i < M; ++i) {
    double row = 0.0;
    for (std::size_t j = 0; j < M; ++j) {
      const double p = transition[i * M + j];
      require(std::isfinite(p) && p >= 0.0 && p <= 1.0, "ImmOptions.transition",
              "entry (" + std::to_string(i) + "," + std::to_string(j) + ") is not a probability");
      row += p;
    }
    require(std::fabs(row - 1.0) < 1e-9, "ImmOptions.transition",
            "row " + std::to_string(i) + " does not sum to 1");
  }
  double total = 0.0;
  for (double p : initial_probabilities) {
    require(std::isfinite(p) && p >= 0.0, "ImmOptions.initial_probabilities", "expected probabilities ≥ 0");
    total += p;
  }
  require(std::fabs(total - 1.0) < 1e-9, "ImmOptions.initial_probabilities", "expected a sum of 1");
  for (std::size_t j = 0; j < M; ++j) {
    const auto& m = models[j];
    const std::string w = "ImmOptions.models[" + std::to_string(j) + "]";
    require(std::isfinite(m.process_noise) && m.process_noise >= 0.0, w + ".process_noise", "expected σ ≥ 0");
    try {
      if (m.kind == ImmModelKind::kCurrentStatistical) m.cs.validate();
      if (m.kind == ImmModelKind::kCsParallel) m.cs_parallel.validate();
    } catch (const InputError& e) {
      throw InputError(w + ": " + e.what());
    }
  }
  require(grain_blocks >= 1, "ImmOptions.grain_blocks", "expected ≥ 1");
}

ImmOptions ImmOptions::seed002() {
  ImmOptions o;
  ImmModelSpec cs;
  cs.kind = ImmModelKind::kCsParallel;
  ImmModelSpec ca;
  ca.kind = ImmModelKind::kConstantAcceleration;
  ca.process_noise = 5.0;  // seed 002 §3: σ = 5 m/s²
  o.models = {cs, ca};
  o.transition = {0.97, 0.03, 0.03, 0.97};
  o.initial_probabilities = {0.5, 0.5};
  return o;
}

ImmBank::ImmBank(int d, std::size_t n, const ImmOptions& options, const BpNetwork& network)
    : d_(d), n_(n), options_(options) {
  options_.validate();
  const int M = static_cast<int>(options_.models.size());
  int max_order = 0;
  for (int j = 0; j < M; ++j) {
    ImmModel m;
    m.spec = options_.models[j];
    if (m.spec.kind == ImmModelKind::kCsParallel)
      m.parallel = std::make_unique<CsParallelBank>(d, n, network);
    else
      m.bank = KinematicBank(d, m.spec.order(), n);
    if (m.spec.order() > max_order) max_order = m.spec.order(), largest_ = j;
    models_.push_back(std::move(m));
  }
  combined_ = KinematicBank(d, max_order, n);
  mu_.resize(M * n);
  cbar_.resize(M * n);
  ll_.assign(M, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i)
    for (int j = 0; j < M; ++j) mu_[j * n + i] = options_.initial_probabilities[j];
}

void ImmBank::initialise(std::size_t i, const Eigen::VectorXd& z1, const Eigen::MatrixXd& R1,
                         const Eigen::VectorXd& z2, const Eigen::MatrixXd& R2, double dt,
                         double accel_variance) {
  for (auto& m : models_) {
    two_point_initialise(m.filter(), i, z1, R1, z2, R2, dt, accel_variance);
    if (m.parallel) {
      two_point_initialise(m.parallel->f1, i, z1, R1, z2, R2, dt, accel_variance);
      m.parallel->scale[i] = 1.0;
    }
  }
  two_point_initialise(combined_, i, z1, R1, z2, R2, dt, accel_variance);
  for (int j = 0; j < num_models(); ++j) mu_[j * n_ + i] = options_.initial_probabilities[j];
}

namespace {

constexpr int W = kBankLanes;
inline int pk(int D, int r, int c) {
  if (r > c) std::swap(r, c);
  return r * D - r * (r - 1) / 2 + (c - r);
}

// A model's block as seen in another space of dimension D: components below own_dim come from
// `own`, the rest from `fill` (dimension fill_dim ≥ D); cross terms between the two parts are 0.
struct Extended {
  const double* own;
  int own_dim;
  const double* fill;
  int fill_dim;
  double x(int c, int l) const { return c < own_dim ? own[c * W + l] : fill[c * W + l]; }
  double P(int r, int c, int l) const {
    if (r < own_dim && c < own_dim) return own[(own_dim + pk(own_dim, r, c)) * W + l];
    if (r >= own_dim && c >= own_dim) return fill[(fill_dim + pk(fill_dim, r, c)) * W + l];
    return 0.0;
  }
};

// Moment-matched mixture of `count` extended estimates with weights w into dst (dimension D).
void mix_into(double* dst, int D, const Extended* src, const double* w, int count, int l) {
  double x[9];
  for (int c = 0; c < D; ++c) {
    x[c] = 0.0;
    for (int i = 0; i < count; ++i) x[c] += w[i] * src[i].x(c, l);
  }
  for (int r = 0; r < D; ++r)
    for (int c = r; c < D; ++c) {
      double p = 0.0;
      for (int i = 0; i < count; ++i)
        p += w[i] * (src[i].P(r, c, l) + (src[i].x(r, l) - x[r]) * (src[i].x(c, l) - x[c]));
      dst[(D + pk(D, r, c)) * W + l] = p;
    }
  for (int c = 0; c < D; ++c) dst[c * W + l] = x[c];
}

}  // namespace

FilterStepSummary imm_bank_step(ImmBank& bank, double dt, const PositionScan& scan, InnovationOutput out) {
  const ImmOptions& o = bank.options_;
  const int M = bank.num_models();
  const std::size_t n = bank.n_;
  require(std::isfinite(dt) && dt >= 0.0, "imm_bank_step.dt", "expected a finite scan interval ≥ 0");
  block::check_scan(scan, out, n, bank.d_, "imm_bank_step.scan");
  const std::size_t blocks = bank.combined_.num_blocks();

  // 1–2. Mixing (seed 002 Eqs. 6–7). Sources are copied per block before any model is overwritten.
  parallel_for_range(blocks, o.grain_blocks, [&](std::size_t b0, std::size_t b1) {
    std::vector<std::vector<double>> copy(M);
    std::vector<Extended> src(M);
    std::vector<double> w(M);
    for (std::size_t b = b0; b < b1; ++b) {
      for (int j = 0; j < M; ++j) {
        const KinematicBank& f = bank.models_[j].filter();
        copy[j].assign(f.block(b), f.block(b) + f.block_stride());
      }
      for (int l = 0; l < W; ++l) {
        const std::size_t i = b * W + l;
        if (i >= n) break;
        for (int j = 0; j < M; ++j) {
          double cbar = 0.0;
          for (int s = 0; s < M; ++s) cbar += o.transition[s * M + j] * bank.mu_[s * n + i];
          bank.cbar_[j * n + i] = cbar;
          for (int s = 0; s < M; ++s)
            w[s] =
                cbar > 1e-300 ? o.transition[s * M + j] * bank.mu_[s * n + i] / cbar : (s == j ? 1.0 : 0.0);
          KinematicBank& f = bank.models_[j].filter();
          const int Dj = f.dim();
          // A larger source is truncated (its own prefix); a smaller one is extended by model j.
          for (int s = 0; s < M; ++s) {
            const int Ds = bank.models_[s].filter().dim();
            src[s] = Ds >= Dj ? Extended{copy[s].data(), Ds, copy[s].data(), Ds}
                              : Extended{copy[s].data(), Ds, copy[j].data(), Dj};
          }
          mix_into(f.block(b), Dj, src.data(), w.data(), M, l);
        }
      }
    }
  });

  // 3. Model-matched filtering; each bank step is itself parallel.
  for (int j = 0; j < M; ++j) {
    ImmModel& m = bank.models_[j];
    InnovationOutput mo{{}, bank.ll_[j]};
    switch (m.spec.kind) {
      case ImmModelKind::kConstantVelocity:
      case ImmModelKind::kConstantAcceleration: {
        KalmanOptions ko;
        ko.model = static_cast<KalmanModel>(m.spec.order());
        ko.process_noise = m.spec.process_noise;
        kalman_bank_step(m.bank, dt, scan, ko, mo);
        break;
      }
      case ImmModelKind::kCurrentStatistical:
        cs_bank_step(m.bank, dt, scan, m.spec.cs, {}, mo);
        break;
      case ImmModelKind::kCsParallel:
        cs_parallel_step(*m.parallel, dt, scan, m.spec.cs_parallel, mo);
        break;
    }
  }

  // 4–5. Probabilities (Eq. 9, in log space) and the combined estimate (Eq. 8).
  const int L = bank.largest_;
  parallel_for_range(blocks, o.grain_blocks, [&](std::size_t b0, std::size_t b1) {
    std::vector<Extended> src(M);
    std::vector<double> w(M);
    for (std::size_t b = b0; b < b1; ++b) {
      const KinematicBank& big = bank.models_[L].filter();
      const int D = big.dim();
      for (int l = 0; l < W; ++l) {
        const std::size_t i = b * W + l;
        if (i >= n) break;
        double top = -INFINITY;
        for (int j = 0; j < M; ++j)
          if (bank.cbar_[j * n + i] > 0.0) top = std::max(top, bank.ll_[j][i]);
        double total = 0.0;
        for (int j = 0; j < M; ++j) {
          const double c = bank.cbar_[j * n + i];
          w[j] = c > 0.0 ? c * std::exp(bank.ll_[j][i] - top) : 0.0;
          total += w[j];
        }
        for (int j = 0; j < M; ++j) {
          w[j] /= total;
          bank.mu_[j * n + i] = w[j];
        }
        if (!out.log_likelihood.empty()) out.log_likelihood[i] = top + std::log(total);
        for (int j = 0; j < M; ++j) {
          const KinematicBank& f = bank.models_[j].filter();
          src[j] = {f.block(b), f.dim(), big.block(b), D};
        }
        mix_into(bank.combined_.block(b), D, src.data(), w.data(), M, l);
      }
    }
  });
  FilterStepSummary s;
  s.tracks = n;
  s.updated = scan.detected.empty() ? n : 0;
  for (uint8_t f : scan.detected) s.updated += f != 0;
  return s;
}

}  // namespace trackassoc
