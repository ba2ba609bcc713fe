#include "kernels/hopfield/hopfield_energy.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "kernels/core/parallel.hpp"

namespace trackassoc {

NormalisedCost normalise_cost(const CostTensor3& cost, float inf_margin) {
  NormalisedCost out;
  out.n1 = cost.n1;
  out.n2 = cost.n2;
  out.n3 = cost.n3;
  // Min and max over fixed chunks in parallel (exact, so independent of the split), then the map.
  constexpr std::size_t kChunk = 65536;
  const std::size_t K = cost.size(), chunks = (K + kChunk - 1) / kChunk;
  std::vector<float> chunk_lo(chunks, std::numeric_limits<float>::infinity()),
      chunk_hi(chunks, -std::numeric_limits<float>::infinity());
  std::vector<uint8_t> chunk_inf(chunks, 0);
  parallel_for_range(chunks, 1, [&](std::size_t tb, std::size_t te) {
    for (std::size_t t = tb; t < te; ++t) {
      // Local accumulators: the chunk_lo/hi entries of two threads share a cache line.
      float l = std::numeric_limits<float>::infinity(), h = -l;
      bool inf = false;
      for (std::size_t a = t * kChunk, e = std::min(K, a + kChunk); a < e; ++a) {
        const float b = cost.cost[a];
        if (std::isfinite(b)) {
          l = std::min(l, b);
          h = std::max(h, b);
        } else {
          inf = true;
        }
      }
      chunk_lo[t] = l;
      chunk_hi[t] = h;
      chunk_inf[t] = inf;
    }
  });
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (std::size_t t = 0; t < chunks; ++t) {
    lo = std::min(lo, chunk_lo[t]);
    hi = std::max(hi, chunk_hi[t]);
  }
  if (!(lo <= hi)) lo = hi = 0.f;  // no finite entry
  out.b_min = lo;
  out.b_range = hi > lo ? hi - lo : 1.f;
  const float inv = 1.f / out.b_range;
  const bool any_infinite = std::any_of(chunk_inf.begin(), chunk_inf.end(), [](uint8_t x) { return x != 0; });
  out.c_lo = any_infinite ? std::min(0.f, 1.f + inf_margin) : 0.f;
  out.c_hi = any_infinite ? std::max(1.f, 1.f + inf_margin) : 1.f;
  out.c.resize(K);
  parallel_for_range(K, kChunk, [&](std::size_t ab, std::size_t ae) {
    for (std::size_t a = ab; a < ae; ++a) {
      const float b = cost.cost[a];
      out.c[a] = std::isfinite(b) ? std::clamp((b - lo) * inv, 0.f, 1.f) : 1.f + inf_margin;
    }
  });
  return out;
}

HopfieldMarginals compute_marginals(std::span<const uint8_t> V, int32_t n1, int32_t n2, int32_t n3,
                                    bool lines) {
  HopfieldMarginals m;
  m.R.assign(n1, 0);
  m.S.assign(n2, 0);
  m.T.assign(n3, 0);
  if (lines) {
    m.Lij.assign(static_cast<std::size_t>(n1) * n2, 0);
    m.Lik.assign(static_cast<std::size_t>(n1) * n3, 0);
    m.Ljk.assign(static_cast<std::size_t>(n2) * n3, 0);
  }
  std::size_t a = 0;
  for (int32_t i = 0; i < n1; ++i)
    for (int32_t j = 0; j < n2; ++j)
      for (int32_t k = 0; k < n3; ++k, ++a) {
        const int32_t v = V[a];
        m.R[i] += v;
        m.S[j] += v;
        m.T[k] += v;
        m.M += v;
        if (lines) {
          m.Lij[static_cast<std::size_t>(i) * n2 + j] += v;
          m.Lik[static_cast<std::size_t>(i) * n3 + k] += v;
          m.Ljk[static_cast<std::size_t>(j) * n3 + k] += v;
        }
      }
  return m;
}

namespace {
double sum_sq(const std::vector<int32_t>& v) {
  double s = 0.0;
  for (int32_t x : v) s += static_cast<double>(x) * x;
  return s;
}
double sum_sq_minus_one(const std::vector<int32_t>& v) {
  double s = 0.0;
  for (int32_t x : v) s += static_cast<double>(x - 1) * (x - 1);
  return s;
}
}  // namespace

double hopfield_energy(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c,
                       std::span<const uint8_t> V) {
  assert(V.size() == c.size());
  const bool lines = form == HopfieldEnergy::kPrinted;
  const HopfieldMarginals m = compute_marginals(V, c.n1, c.n2, c.n3, lines);
  double cost_term = 0.0;
  for (std::size_t a = 0; a < V.size(); ++a)
    if (V[a]) cost_term += c.c[a];
  const double dM = static_cast<double>(m.M) - w.N;
  double e = 0.5 * w.D * dM * dM + static_cast<double>(w.E) * cost_term;
  if (form == HopfieldEnergy::kFullPlane) {
    e += 0.5 * w.A * sum_sq_minus_one(m.R) + 0.5 * w.B * sum_sq_minus_one(m.S) +
         0.5 * w.C * sum_sq_minus_one(m.T);
  } else {
    // seed 000 Eq. 11: Σ_ijk V_ijk Σ_{y≠j,z≠k} V_iyz = Σ_i R_i² − Σ L_ij² − Σ L_ik² + M.
    const double Lij2 = sum_sq(m.Lij), Lik2 = sum_sq(m.Lik), Ljk2 = sum_sq(m.Ljk);
    const double M = static_cast<double>(m.M);
    e += w.A * (sum_sq(m.R) - Lij2 - Lik2 + M) + w.B * (sum_sq(m.S) - Lij2 - Ljk2 + M) +
         w.C * (sum_sq(m.T) - Lik2 - Ljk2 + M);
  }
  return e;
}

double delta_on(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c,
                const HopfieldMarginals& m, std::span<const uint8_t> V, int32_t i, int32_t j, int32_t k) {
  const std::size_t a = (static_cast<std::size_t>(i) * c.n2 + j) * c.n3 + k;
  const int32_t v = V[a];
  if (form == HopfieldEnergy::kFullPlane)
    return full_plane_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v, m.M - v, c.c[a]);
  return printed_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v,
                          m.Lij[static_cast<std::size_t>(i) * c.n2 + j] - v,
                          m.Lik[static_cast<std::size_t>(i) * c.n3 + k] - v,
                          m.Ljk[static_cast<std::size_t>(j) * c.n3 + k] - v, m.M - v, c.c[a]);
}

// W_ab for a ≠ b, derived from each energy (see the header):
//   full plane: −A[i=x] − B[j=y] − C[k=z] − D,            θ_a = −(A+B+C)/2 + D(½−N) + E·ĉ_a
//   printed:    −2A[i=x][j≠y][k≠z] − 2B[..] − 2C[..] − D,  θ_a = D(½−N) + E·ĉ_a
NaiveHopfieldNetwork::NaiveHopfieldNetwork(HopfieldEnergy form, const HopfieldWeights& w,
                                           const NormalisedCost& c) {
  const std::size_t K = c.size();
  W_.assign(K * K, 0.f);
  theta_.resize(K);
  const bool full = form == HopfieldEnergy::kFullPlane;
  auto decode = [&](std::size_t a, int32_t& i, int32_t& j, int32_t& k) {
    k = static_cast<int32_t>(a % c.n3);
    j = static_cast<int32_t>((a / c.n3) % c.n2);
    i = static_cast<int32_t>(a / (static_cast<std::size_t>(c.n3) * c.n2));
  };
  for (std::size_t a = 0; a < K; ++a) {
    int32_t i, j, k;
    decode(a, i, j, k);
    for (std::size_t b = 0; b < K; ++b) {
      if (a == b) continue;
      int32_t x, y, z;
      decode(b, x, y, z);
      const bool si = i == x, sj = j == y, sk = k == z;
      double wab = -w.D;
      if (full) {
        wab -= w.A * si + w.B * sj + w.C * sk;
      } else {
        wab -= 2.0 * (w.A * (si && !sj && !sk) + w.B * (sj && !si && !sk) + w.C * (sk && !si && !sj));
      }
      W_[a * K + b] = static_cast<float>(wab);
    }
    theta_[a] =
        (full ? -0.5 * (w.A + w.B + w.C) : 0.0) + w.D * (0.5 - w.N) + static_cast<double>(w.E) * c.c[a];
  }
  constant_ = 0.5 * w.D * static_cast<double>(w.N) * w.N;
  if (full) constant_ += 0.5 * (w.A * c.n1 + w.B * c.n2 + w.C * c.n3);
}

double NaiveHopfieldNetwork::net_input(std::span<const uint8_t> V, std::size_t a) const {
  const std::size_t K = size();
  const float* row = &W_[a * K];
  double s = 0.0;
  for (std::size_t b = 0; b < K; ++b) s += static_cast<double>(row[b]) * V[b];
  return s - theta_[a];
}

double NaiveHopfieldNetwork::energy(std::span<const uint8_t> V) const {
  const std::size_t K = size();
  double quad = 0.0, lin = 0.0;
  for (std::size_t a = 0; a < K; ++a) {
    if (!V[a]) continue;
    lin += theta_[a];
    const float* row = &W_[a * K];
    for (std::size_t b = 0; b < K; ++b) quad += static_cast<double>(row[b]) * V[b];
  }
  return -0.5 * quad + lin + constant_;
}

void NaiveHopfieldNetwork::sync_sweep(std::span<const uint8_t> V, std::span<uint8_t> out) const {
  for (std::size_t a = 0; a < size(); ++a) {
    const double net = net_input(V, a);
    out[a] = net > 0 ? 1 : (net < 0 ? 0 : V[a]);  // seed 000 Eq. 10 with 0/1 states
  }
}

void NaiveHopfieldNetwork::async_sweep(std::span<uint8_t> V, std::span<const uint32_t> order) const {
  for (uint32_t a : order) {
    const double net = net_input(V, a);
    if (net > 0)
      V[a] = 1;
    else if (net < 0)
      V[a] = 0;
  }
}

}  // namespace trackassoc
