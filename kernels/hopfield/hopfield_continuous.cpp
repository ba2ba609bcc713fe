#include "kernels/hopfield/hopfield_continuous.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "kernels/core/parallel.hpp"

namespace trackassoc {

namespace {

// ½(1 + tanh(x)) = 1 / (1 + e^{−2x}), with e^y = 2^{y·log2 e} split into an integer power (built
// in the exponent bits) and a degree-5 polynomial for 2^f, f ∈ [0, 1): relative error < 3e-7,
// and branch-free, so the Euler loop vectorises (std::tanh does not).
__attribute__((always_inline, optimize("fast-math"))) inline float half_one_plus_tanh(float x) {
  float y = -2.f * 1.44269504f * x;
  y = y > 126.f ? 126.f : (y < -126.f ? -126.f : y);
  const float fl = __builtin_floorf(y);
  const float f = y - fl;
  float p = 1.8775767e-3f;
  p = p * f + 8.9893397e-3f;
  p = p * f + 5.5826318e-2f;
  p = p * f + 2.4015361e-1f;
  p = p * f + 6.9315308e-1f;
  p = p * f + 9.9999994e-1f;
  const int32_t bits = (static_cast<int32_t>(fl) + 127) << 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return 1.f / (1.f + p * scale);
}

// The Euler step of one neuron with net input h = −∂E/∂V (the header's form): u ← decay·u +
// dt·(h + self·(V − ½)), V ← ½(1 + tanh(u·gain)). Raises dmax to |ΔV|; returns the new V.
__attribute__((always_inline, optimize("fast-math"))) inline float euler_neuron(float h, float self,
                                                                                float decay, float dt,
                                                                                float gain, float& u,
                                                                                float& V, float& dmax) {
  u = decay * u + dt * (h + self * (V - 0.5f));
  const float nv = half_one_plus_tanh(u * gain);
  const float d = nv - V;
  const float ad = d < 0.f ? -d : d;
  dmax = ad > dmax ? ad : dmax;
  V = nv;
  return nv;
}

// One row (i, j) of the sync Euler step; returns Σ_k V. Reassociation (fast-math, this function
// only) lets GCC vectorise the row sums and the max; the order is fixed per row, so the result
// still does not depend on the thread count.
__attribute__((optimize("fast-math"))) float euler_row(int32_t n3, float base, const float* __restrict t,
                                                       const float* __restrict cc, float E, float dt,
                                                       float decay, float gain, float self,
                                                       float* __restrict u, float* __restrict V,
                                                       float* __restrict lik, float& dmax) {
  float lij = 0.f, m = dmax;
  for (int32_t k = 0; k < n3; ++k) {
    const float nv = euler_neuron(-(base + t[k] + E * cc[k]), self, decay, dt, gain, u[k], V[k], m);
    lij += nv;
    lik[k] += nv;
  }
  dmax = m;
  return lij;
}

// One i-slice of the sync Euler step: its n2·n3 neurons in one flat loop (one vector tail per
// slice instead of one per row), with P[j·n3 + k] = B(S_j − 1) + C(T_k − 1) shared by all slices and
// base = A(R_i − 1) + D(M − N). Returns max |ΔV| over the slice. Reassociation (fast-math, this
// function only) lets GCC vectorise the max; the order is fixed, so the result does not depend on
// the thread count.
__attribute__((optimize("fast-math"))) float euler_slice(std::size_t m, float base, const float* __restrict P,
                                                         const float* __restrict cc, float E, float dt,
                                                         float decay, float gain, float self,
                                                         float* __restrict u, float* __restrict V) {
  float dmax = 0.f;
  for (std::size_t q = 0; q < m; ++q)
    euler_neuron(-(base + P[q] + E * cc[q]), self, decay, dt, gain, u[q], V[q], dmax);
  return dmax;
}

// The line sums of one slice V[j·n3 + k]: lij[j] = Σ_k V, lik[k] = Σ_j V (fixed order).
__attribute__((optimize("fast-math"))) void slice_line_sums(int32_t n2, int32_t n3, const float* __restrict V,
                                                            float* __restrict lij, float* __restrict lik) {
  for (int32_t k = 0; k < n3; ++k) lik[k] = 0.f;
  for (int32_t j = 0; j < n2; ++j) {
    const float* __restrict row = V + static_cast<std::size_t>(j) * n3;
    float sum = 0.f;
    for (int32_t k = 0; k < n3; ++k) {
      sum += row[k];
      lik[k] += row[k];
    }
    lij[j] = sum;
  }
}

}  // namespace

ContinuousNetwork::ContinuousNetwork(const NormalisedCost& cost)
    : c(&cost), u(cost.size(), 0.f), V(cost.size(), 0.f), R(cost.n1), S(cost.n2), T(cost.n3) {}

void ContinuousNetwork::initialise(float u_init, float noise, float u0, CounterRng& rng) {
  for (std::size_t a = 0; a < u.size(); ++a) {
    u[a] = u_init + noise * static_cast<float>(rng.normal());
    V[a] = half_one_plus_tanh(u[a] / u0);
  }
  recompute_marginals();
}

void ContinuousNetwork::recompute_marginals() {
  const int32_t n1 = c->n1, n2 = c->n2, n3 = c->n3;
  std::fill(R.begin(), R.end(), 0.0);
  std::fill(S.begin(), S.end(), 0.0);
  std::fill(T.begin(), T.end(), 0.0);
  M = 0.0;
  std::size_t a = 0;
  for (int32_t i = 0; i < n1; ++i)
    for (int32_t j = 0; j < n2; ++j)
      for (int32_t k = 0; k < n3; ++k, ++a) {
        R[i] += V[a];
        S[j] += V[a];
        T[k] += V[a];
      }
  for (double r : R) M += r;
}

double ContinuousNetwork::energy(const HopfieldWeights& w) const {
  double e = 0.0, cost = 0.0;
  for (double r : R) e += 0.5 * w.A * (r - 1) * (r - 1);
  for (double s : S) e += 0.5 * w.B * (s - 1) * (s - 1);
  for (double t : T) e += 0.5 * w.C * (t - 1) * (t - 1);
  for (std::size_t a = 0; a < V.size(); ++a) cost += static_cast<double>(V[a]) * c->c[a];
  return e + 0.5 * w.D * (M - w.N) * (M - w.N) + w.E * cost;
}

float continuous_sync_step(ContinuousNetwork& net, const ContinuousParams& p) {
  const NormalisedCost& c = *net.c;
  const int32_t n1 = c.n1, n2 = c.n2, n3 = c.n3;
  const HopfieldWeights& w = p.w;
  const float decay = p.tau > 0.f ? 1.f - p.dt / p.tau : 1.f;
  const float inv_u0 = 1.f / p.u0;
  const std::size_t m = static_cast<std::size_t>(n2) * n3;
  // Slices of up to kFlatSlice neurons run as one flat loop over P[j·n3 + k] = B(S_j − 1) +
  // C(T_k − 1), shared by every slice: one vector tail per slice instead of one per row (n = 100:
  // 0.51 → 0.35 ms per step on 1 thread). Larger slices run row by row, where P and the slice would
  // crowd the L2 cache (n = 200: the flat loop is 10–25 % slower).
  constexpr std::size_t kFlatSlice = 16384;
  const bool flat = m <= kFlatSlice;
  std::vector<float> tk(n3), P(flat ? m : 0);
  for (int32_t k = 0; k < n3; ++k) tk[k] = static_cast<float>(w.C * (net.T[k] - 1.0));
  if (flat)
    for (int32_t j = 0; j < n2; ++j) {
      const float sj = static_cast<float>(w.B * (net.S[j] - 1.0));
      for (int32_t k = 0; k < n3; ++k) P[static_cast<std::size_t>(j) * n3 + k] = sj + tk[k];
    }
  const float Dterm = static_cast<float>(w.D * (net.M - w.N));
  // Per-slice line sums: Lij for S, Lik for T (float over one slice), reduced below in double in a
  // fixed order, so the result does not depend on the thread count.
  std::vector<float> Lij(static_cast<std::size_t>(n1) * n2), Lik(static_cast<std::size_t>(n1) * n3, 0.f);
  std::vector<float> slice_max(n1, 0.f);
  parallel_for_range(static_cast<std::size_t>(n1), 1, [&](std::size_t ib, std::size_t ie) {
    const int32_t N2 = n2, N3 = n3;
    const float E = w.E, dt = p.dt, dec = decay, g = inv_u0;
    const float self = p.self_excitation * (w.A + w.B + w.C + w.D);
    for (std::size_t i = ib; i < ie; ++i) {
      const float Ri = static_cast<float>(w.A * (net.R[i] - 1.0));
      float* __restrict lik = Lik.data() + i * N3;
      if (flat) {
        slice_max[i] = euler_slice(m, Ri + Dterm, P.data(), c.c.data() + i * m, E, dt, dec, g, self,
                                   net.u.data() + i * m, net.V.data() + i * m);
        slice_line_sums(N2, N3, net.V.data() + i * m, Lij.data() + i * N2, lik);
        continue;
      }
      float dmax = 0.f;
      for (int32_t j = 0; j < N2; ++j) {
        const std::size_t row = (i * N2 + j) * static_cast<std::size_t>(N3);
        const float base = Ri + static_cast<float>(w.B * (net.S[j] - 1.0)) + Dterm;
        Lij[i * N2 + j] = euler_row(N3, base, tk.data(), c.c.data() + row, E, dt, dec, g, self,
                                    net.u.data() + row, net.V.data() + row, lik, dmax);
      }
      slice_max[i] = dmax;
    }
  });
  std::fill(net.S.begin(), net.S.end(), 0.0);
  std::fill(net.T.begin(), net.T.end(), 0.0);
  net.M = 0.0;
  for (int32_t i = 0; i < n1; ++i) {
    double r = 0.0;
    for (int32_t j = 0; j < n2; ++j) {
      r += Lij[static_cast<std::size_t>(i) * n2 + j];
      net.S[j] += Lij[static_cast<std::size_t>(i) * n2 + j];
    }
    for (int32_t k = 0; k < n3; ++k) net.T[k] += Lik[static_cast<std::size_t>(i) * n3 + k];
    net.R[i] = r;
    net.M += r;
  }
  return *std::max_element(slice_max.begin(), slice_max.end());
}

float continuous_async_step(ContinuousNetwork& net, const ContinuousParams& p,
                            std::span<const uint32_t> order) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = p.w;
  const float decay = p.tau > 0.f ? 1.f - p.dt / p.tau : 1.f;
  const float inv_u0 = 1.f / p.u0;
  float dmax = 0.f;
  const NeuronIndexer index(c);
  const std::size_t K = order.size();
  constexpr std::size_t kAhead = 16;  // u, V and ĉ are read at random: prefetch them
  for (std::size_t q = 0; q < K; ++q) {
    if (q + kAhead < K) {
      const uint32_t b = order[q + kAhead];
      __builtin_prefetch(net.u.data() + b, 1);
      __builtin_prefetch(net.V.data() + b, 1);
      __builtin_prefetch(c.c.data() + b);
    }
    const uint32_t a = order[q];
    const auto [i, j, k] = index(a);
    const double h = -(w.A * (net.R[i] - 1.0) + w.B * (net.S[j] - 1.0) + w.C * (net.T[k] - 1.0) +
                       w.D * (net.M - w.N) + static_cast<double>(w.E) * c.c[a]) +
                     p.self_excitation * (w.A + w.B + w.C + w.D) * (net.V[a] - 0.5);
    net.u[a] = decay * net.u[a] + p.dt * static_cast<float>(h);
    const float nv = half_one_plus_tanh(net.u[a] * inv_u0);
    const double d = static_cast<double>(nv) - net.V[a];
    dmax = std::max(dmax, static_cast<float>(std::abs(d)));
    net.V[a] = nv;
    net.R[i] += d;
    net.S[j] += d;
    net.T[k] += d;
    net.M += d;
  }
  net.recompute_marginals();  // removes the drift of the incremental sums
  return dmax;
}

}  // namespace trackassoc
