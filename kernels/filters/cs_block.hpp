// Block kernel of the CS prediction, shared by cs_filter.cpp and cs_parallel.cpp (internal header).
#pragma once

#include <Eigen/Core>

#include "kernels/filters/cs_filter.hpp"
#include "kernels/filters/kalman_block.hpp"

namespace trackassoc::block {

// The scan-constant part of a CS prediction: Φ for the covariance, the CA matrix for the state
// (Φx̂ + Uā with ā = â), and Singer's q for step dt.
struct CsContext {
  double Fx[3][3][W], Fp[3][3][W];
  Eigen::Matrix3d q;
  CsOptions options;
  CsContext(const CsOptions& o, double dt) : options(o) {
    const Eigen::Matrix3d Phi = cs_transition(o.manoeuvre_frequency, dt);
    const Eigen::MatrixXd Fca = kinematic_transition(3, dt);
    q = cs_process_noise_shape(o.manoeuvre_frequency, dt);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int l = 0; l < W; ++l) {
          Fx[i][j][l] = Fca(i, j);
          Fp[i][j][l] = Phi(i, j);
        }
  }
};

// CS prediction of one block with Q = scale·σ_w²(ā)·q per axis (seed 002 Eqs. 1–2); writes the
// unscaled per-axis Q (σ_w²(ā)·q) to q_out.
template <int d>
inline void cs_predict(double* blk, const CsContext& cx, const double (&scale)[W], double (&q_out)[d][6][W]) {
  constexpr int n = 3;
  double Q1[d][packed(n)][W];
  const double two_alpha = 2.0 * cx.options.manoeuvre_frequency;
  for (int a = 0; a < d; ++a) {
    const double* acc = blk + (2 * d + a) * W;
    for (int l = 0; l < W; ++l) {
      const double sw2 = two_alpha * cs_accel_variance(acc[l], cx.options);
      for (int r = 0; r < n; ++r)
        for (int c = r; c < n; ++c) {
          const int k = pidx(n, r, c);
          q_out[a][k][l] = sw2 * cx.q(r, c);
          Q1[a][k][l] = scale[l] * q_out[a][k][l];
        }
    }
  }
  predict_covariance<d, n>(blk, cx.Fp, Q1);
  predict_state<d, n>(blk, cx.Fx);
}

// P += s·Q (Q per axis as written by cs_predict).
template <int d>
inline void add_process_noise(double* blk, const double (&q)[d][6][W], const double (&s)[W]) {
  constexpr int D = 3 * d;
  double* p = blk + D * W;
  for (int a = 0; a < d; ++a)
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) {
        double* pd = p + pidx(D, r * d + a, c * d + a) * W;
        for (int l = 0; l < W; ++l) pd[l] += s[l] * q[a][pidx(3, r, c)][l];
      }
}

}  // namespace trackassoc::block
