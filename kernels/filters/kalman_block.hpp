// Block kernels shared by the filter banks (kalman_bank, cs_filter, imm): one Kalman predict and
// one position update over a block of kBankLanes tracks stored as a Matriplex (mkFit; Cerati et
// al., "Kalman filter tracking on parallel architectures", 2015): component c of lane l lives at
// blk[c·W + l], so every arithmetic statement below is a loop over W contiguous lanes that the
// compiler turns into SIMD instructions.
//
// State of a kinematic model of spatial dimension d and derivative order n (n = 2: position and
// velocity; n = 3: position, velocity, acceleration) has D = n·d components ordered by derivative
// block: x, y[, z], vx, vy[, vz][, ax, ay[, az]]. Component c has axis c % d and order c / d. The
// covariance follows as the packed upper triangle (row-major) of the D×D matrix.
//
// The transition is F = F1 ⊗ I_d with a per-lane n×n upper-triangular F1 (same for every axis),
// and the process noise is block-diagonal over axes: Q = blkdiag_a(Q1_a), Q1_a an n×n matrix per
// axis and lane. That covers the CV/CA Kalman filters (Q1_a identical) and the "current"
// statistical model (Q1_a scaled per axis by the adaptive acceleration variance).
//
// Internal header: included by the kernel .cpp files only.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <type_traits>

#include "kernels/filters/kalman_bank.hpp"

namespace trackassoc::block {

inline constexpr int W = 8;  // lanes per block (one AVX-512 register of doubles, two AVX2)

constexpr int packed(int D) { return D * (D + 1) / 2; }
constexpr int pidx(int D, int r, int c) { return r <= c ? r * D - r * (r - 1) / 2 + (c - r) : pidx(D, c, r); }

template <int d, int n>
struct Shape {
  static constexpr int D = d * n;              // state dimension
  static constexpr int NP = packed(D);         // packed covariance entries
  static constexpr int NQ = packed(n);         // packed per-axis process-noise entries
  static constexpr int stride = (D + NP) * W;  // doubles per block: state then covariance
};

// Per-lane model of one prediction: F1[i][j] (upper triangle used) and Q1[axis][pidx(n,i,j)].
template <int d, int n>
struct LaneModel {
  double F1[n][n][W];
  double Q1[d][packed(n)][W];
};

// x ← F x on one block, F = F1 ⊗ I_d.
template <int d, int n>
inline void predict_state(double* __restrict blk, const double (&F1)[n][n][W]) {
  constexpr int D = d * n;
  double* __restrict x = blk;
  double xn[D][W];
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r) {
    const int ax = r % d, orr = r / d;
    for (int l = 0; l < W; ++l) xn[r][l] = 0.0;
#pragma GCC unroll 64
    for (int ok = orr; ok < n; ++ok)
      for (int l = 0; l < W; ++l) xn[r][l] += F1[orr][ok][l] * x[(ok * d + ax) * W + l];
  }
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r)
    for (int l = 0; l < W; ++l) x[r * W + l] = xn[r][l];
}

// P ← F P Fᵀ + Q on one block (Bar-Shalom, Li, Kirubarajan 2001, Eq. 5.2.3-9), upper triangle.
template <int d, int n>
inline void predict_covariance(double* __restrict blk, const double (&F1)[n][n][W],
                               const double (&Q1)[d][packed(n)][W]) {
  constexpr int D = d * n;
  double* __restrict p = blk + D * W;
  // FP[r][c] = Σ_k F[r][k] P[k][c], F[r][k] = F1[or][ok] when axis(r) = axis(k) and ok ≥ or.
  double fp[D][D][W];
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r) {
    const int ax = r % d, orr = r / d;
#pragma GCC unroll 64
    for (int c = 0; c < D; ++c) {
      for (int l = 0; l < W; ++l) fp[r][c][l] = 0.0;
#pragma GCC unroll 64
      for (int ok = orr; ok < n; ++ok) {
        const int k = ok * d + ax;
        const double* pk = p + pidx(D, k, c) * W;
        for (int l = 0; l < W; ++l) fp[r][c][l] += F1[orr][ok][l] * pk[l];
      }
    }
  }
// P'[r][c] = Σ_k FP[r][k] F[c][k] + Q[r][c].
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r) {
#pragma GCC unroll 64
    for (int c = r; c < D; ++c) {
      const int ax = c % d, oc = c / d;
      double acc[W];
      for (int l = 0; l < W; ++l) acc[l] = 0.0;
#pragma GCC unroll 64
      for (int ok = oc; ok < n; ++ok) {
        const int k = ok * d + ax;
        for (int l = 0; l < W; ++l) acc[l] += fp[r][k][l] * F1[oc][ok][l];
      }
      if (r % d == ax) {
        const int q = pidx(n, r / d, oc);
        for (int l = 0; l < W; ++l) acc[l] += Q1[ax][q][l];
      }
      double* pd = p + pidx(D, r, c) * W;
      for (int l = 0; l < W; ++l) pd[l] = acc[l];
    }
  }
}

// x ← F x, P ← F P Fᵀ + Q (Bar-Shalom et al. 2001, Eq. 5.2.3-5 and 5.2.3-9).
template <int d, int n>
inline void predict(double* __restrict blk, const LaneModel<d, n>& m) {
  predict_state<d, n>(blk, m.F1);
  predict_covariance<d, n>(blk, m.F1, m.Q1);
}

// Measurement of one block: Cartesian position z (d components) with covariance R (packed d×d),
// and a mask; lanes with detected = 0 keep their predicted state (missed detection).
template <int d>
struct LaneMeasurement {
  double z[d][W];
  double R[packed(d)][W];
  double detected[W];  // 1.0 or 0.0
};

// Optional per-lane outputs of an update: normalised innovation squared νᵀS⁻¹ν and the Gaussian
// log-likelihood log N(ν; 0, S) (the IMM model likelihood, seed 002 Eq. 9). Zero for missed lanes.
struct LaneInnovation {
  double nis[W];
  double log_likelihood[W];
};

// Inverts the symmetric d×d matrix s (packed) lane by lane by the adjugate; returns det in det[].
template <int d>
inline void invert_packed(const double (&s)[packed(d)][W], double (&si)[packed(d)][W], double (&det)[W]) {
  if constexpr (d == 2) {
    for (int l = 0; l < W; ++l) {
      const double a = s[0][l], b = s[1][l], c = s[2][l];
      const double dt = a * c - b * b, inv = 1.0 / dt;
      det[l] = dt;
      si[0][l] = c * inv;
      si[1][l] = -b * inv;
      si[2][l] = a * inv;
    }
  } else {
    static_assert(d == 3);
    for (int l = 0; l < W; ++l) {
      const double a = s[0][l], b = s[1][l], c = s[2][l], e = s[3][l], f = s[4][l], g = s[5][l];
      // [[a b c] [b e f] [c f g]]
      const double A = e * g - f * f, B = c * f - b * g, C = b * f - c * e;
      const double dt = a * A + b * B + c * C, inv = 1.0 / dt;
      det[l] = dt;
      si[0][l] = A * inv;
      si[1][l] = B * inv;
      si[2][l] = C * inv;
      si[3][l] = (a * g - c * c) * inv;
      si[4][l] = (b * c - a * f) * inv;
      si[5][l] = (a * e - b * b) * inv;
    }
  }
}

// Kalman update with H = [I_d 0]: S = P_pp + R, K = P Hᵀ S⁻¹, x ← x + Kν, P ← P − K H P
// (Bar-Shalom et al. 2001, Eq. 5.2.3-11 to 5.2.3-17). P − (PHᵀ) S⁻¹ (HP) is evaluated on the
// upper triangle only, so symmetry is exact.
template <int d, int n>
inline void update(double* __restrict blk, const LaneMeasurement<d>& m, LaneInnovation* out) {
  using Sh = Shape<d, n>;
  constexpr int D = Sh::D;
  constexpr int NR = packed(d);
  double* __restrict x = blk;
  double* __restrict p = blk + D * W;
  double s[NR][W], si[NR][W], det[W];
#pragma GCC unroll 64
  for (int a = 0; a < d; ++a)
#pragma GCC unroll 64
    for (int b = a; b < d; ++b)
      for (int l = 0; l < W; ++l) s[pidx(d, a, b)][l] = p[pidx(D, a, b) * W + l] + m.R[pidx(d, a, b)][l];
  invert_packed<d>(s, si, det);
  double nu[d][W];
#pragma GCC unroll 64
  for (int a = 0; a < d; ++a)
    for (int l = 0; l < W; ++l) nu[a][l] = m.z[a][l] - x[a * W + l];
  // g = S⁻¹ν, so that Kν = P Hᵀ g.
  double g[d][W];
#pragma GCC unroll 64
  for (int a = 0; a < d; ++a) {
    for (int l = 0; l < W; ++l) g[a][l] = 0.0;
#pragma GCC unroll 64
    for (int b = 0; b < d; ++b)
      for (int l = 0; l < W; ++l) g[a][l] += si[pidx(d, a, b)][l] * nu[b][l];
  }
  if (out) {
    for (int l = 0; l < W; ++l) {
      double q = 0.0;
#pragma GCC unroll 64
      for (int a = 0; a < d; ++a) q += nu[a][l] * g[a][l];
      out->nis[l] = q * m.detected[l];
      out->log_likelihood[l] =
          m.detected[l] * (-0.5 * (q + std::log(det[l]) + d * std::log(2.0 * std::numbers::pi)));
    }
  }
  // K = P Hᵀ S⁻¹ (D×d), masked by the detection flag.
  double k[D][d][W];
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r)
#pragma GCC unroll 64
    for (int a = 0; a < d; ++a) {
      for (int l = 0; l < W; ++l) k[r][a][l] = 0.0;
#pragma GCC unroll 64
      for (int b = 0; b < d; ++b) {
        const double* prb = p + pidx(D, r, b) * W;
        for (int l = 0; l < W; ++l) k[r][a][l] += prb[l] * si[pidx(d, b, a)][l];
      }
      for (int l = 0; l < W; ++l) k[r][a][l] *= m.detected[l];
    }
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r) {
    double dx[W];
    for (int l = 0; l < W; ++l) dx[l] = 0.0;
#pragma GCC unroll 64
    for (int a = 0; a < d; ++a)
      for (int l = 0; l < W; ++l) dx[l] += k[r][a][l] * nu[a][l];
    for (int l = 0; l < W; ++l) x[r * W + l] += dx[l];
  }
  // P[r][c] -= Σ_a K[r][a] P[a][c]. The rows a < d of P are read while P is overwritten, so they
  // are copied first.
  double ph[d][D][W];
#pragma GCC unroll 64
  for (int a = 0; a < d; ++a)
#pragma GCC unroll 64
    for (int c = 0; c < D; ++c)
      for (int l = 0; l < W; ++l) ph[a][c][l] = p[pidx(D, a, c) * W + l];
#pragma GCC unroll 64
  for (int r = 0; r < D; ++r)
#pragma GCC unroll 64
    for (int c = r; c < D; ++c) {
      double acc[W];
      for (int l = 0; l < W; ++l) acc[l] = 0.0;
#pragma GCC unroll 64
      for (int a = 0; a < d; ++a)
        for (int l = 0; l < W; ++l) acc[l] += k[r][a][l] * ph[a][c][l];
      double* pd = p + pidx(D, r, c) * W;
      for (int l = 0; l < W; ++l) pd[l] -= acc[l];
    }
}

// Gathers the scan entries of block b (tracks b·W .. b·W+W−1 of n_tracks) into lane arrays.
// Padding lanes get z = 0, R = I and detected = 0.
template <int d>
inline void load_measurement(const PositionScan& scan, std::size_t b, std::size_t n_tracks,
                             LaneMeasurement<d>& m) {
  constexpr int NR = packed(d);
  const std::size_t first = b * W;
  const bool all = scan.detected.empty();
  if (first + W <= n_tracks) {  // full block: contiguous copies the compiler vectorises
    for (int a = 0; a < d; ++a) {
      const double* src = scan.z[a].data() + first;
      for (int l = 0; l < W; ++l) m.z[a][l] = src[l];
    }
    for (int k = 0; k < NR; ++k) {
      const double* src = scan.R[k].data() + first;
      for (int l = 0; l < W; ++l) m.R[k][l] = src[l];
    }
    if (all) {
      for (int l = 0; l < W; ++l) m.detected[l] = 1.0;
    } else {
      const uint8_t* f = scan.detected.data() + first;
      for (int l = 0; l < W; ++l) m.detected[l] = f[l] ? 1.0 : 0.0;
    }
    return;
  }
  for (int l = 0; l < W; ++l) {
    const std::size_t i = first + l;
    const bool valid = i < n_tracks;
    for (int a = 0; a < d; ++a) m.z[a][l] = valid ? scan.z[a][i] : 0.0;
    for (int a = 0; a < d; ++a)
      for (int c = a; c < d; ++c)
        m.R[pidx(d, a, c)][l] = valid ? scan.R[pidx(d, a, c)][i] : (a == c ? 1.0 : 0.0);
    m.detected[l] = valid && (all || scan.detected[i]) ? 1.0 : 0.0;
  }
}

// Scatters the optional innovation outputs of block b.
inline void store_innovation(const InnovationOutput& out, std::size_t b, std::size_t n_tracks,
                             const LaneInnovation& v) {
  const std::size_t first = b * W;
  for (int l = 0; l < W && first + l < n_tracks; ++l) {
    if (!out.nis.empty()) out.nis[first + l] = v.nis[l];
    if (!out.log_likelihood.empty()) out.log_likelihood[first + l] = v.log_likelihood[l];
  }
}

// Calls f(std::integral_constant<int, d>, std::integral_constant<int, n>) for runtime d ∈ {2, 3},
// n ∈ {2, 3}, so that every kernel is compiled for the four fixed shapes.
template <class F>
inline void dispatch(int d, int n, F&& f) {
  using I2 = std::integral_constant<int, 2>;
  using I3 = std::integral_constant<int, 3>;
  if (d == 2 && n == 2)
    f(I2{}, I2{});
  else if (d == 2)
    f(I2{}, I3{});
  else if (n == 2)
    f(I3{}, I2{});
  else
    f(I3{}, I3{});
}

// Checks the spans of a scan against the bank size and dimension (throws InputError).
void check_scan(const PositionScan& scan, const InnovationOutput& out, std::size_t n_tracks, int d,
                const char* where);

}  // namespace trackassoc::block
