#include "kernels/hopfield_discrete.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include "kernels/error.hpp"
#include "kernels/parallel.hpp"

namespace trackassoc {

DiscreteNetwork::DiscreteNetwork(HopfieldEnergy f, const HopfieldWeights& weights, const NormalisedCost& cost)
    : form(f), w(weights), c(&cost), V(cost.size(), 0) {
  m = compute_marginals(V, c->n1, c->n2, c->n3, form == HopfieldEnergy::kPrinted);
}

void DiscreteNetwork::set_state(std::span<const uint8_t> state) {
  V.assign(state.begin(), state.end());
  m = compute_marginals(V, c->n1, c->n2, c->n3, form == HopfieldEnergy::kPrinted);
  hash = 0;
  for (std::size_t a = 0; a < V.size(); ++a)
    if (V[a]) hash ^= zobrist_key(a);
}

double DiscreteNetwork::delta_on(std::size_t a) const {
  const int32_t k = static_cast<int32_t>(a % c->n3);
  const int32_t j = static_cast<int32_t>((a / c->n3) % c->n2);
  const int32_t i = static_cast<int32_t>(a / (static_cast<std::size_t>(c->n3) * c->n2));
  return trackassoc::delta_on(form, w, *c, m, V, i, j, k);
}

// ---------------------------------------------------------------------------------------------
// async: Gauss–Seidel, marginals updated on every flip.

namespace {

// Division by a run-time constant through a double reciprocal with an exact correction
// (indices < 2^32), about 5× faster than an integer division in the async inner loop.
struct FastDivider {
  uint32_t d;
  double inv;
  explicit FastDivider(uint32_t divisor) : d(divisor), inv(1.0 / divisor) {}
  uint32_t div(uint32_t a) const {
    uint32_t q = static_cast<uint32_t>(a * inv);
    if (static_cast<uint64_t>(q) * d > a)
      --q;
    else if (static_cast<uint64_t>(q + 1) * d <= a)
      ++q;
    return q;
  }
};

}  // namespace

int64_t async_sweep(DiscreteNetwork& net, std::span<const uint32_t> order, double temperature,
                    CounterRng* rng) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = net.w;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  const bool glauber = temperature > 0.0 && rng != nullptr;
  HopfieldMarginals& m = net.m;
  const FastDivider div3(static_cast<uint32_t>(c.n3)), div2(static_cast<uint32_t>(c.n2));
  int64_t flips = 0;
  for (uint32_t a : order) {
    const uint32_t ij = div3.div(a);
    const int32_t k = static_cast<int32_t>(a - ij * static_cast<uint32_t>(c.n3));
    const int32_t i = static_cast<int32_t>(div2.div(ij));
    const int32_t j = static_cast<int32_t>(ij - static_cast<uint32_t>(i) * c.n2);
    const int32_t v = net.V[a];
    double dE;
    if (!printed) {
      dE = full_plane_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v, m.M - v, c.c[a]);
    } else {
      dE = printed_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v, m.Lij[ij] - v,
                            m.Lik[static_cast<std::size_t>(i) * c.n3 + k] - v,
                            m.Ljk[static_cast<std::size_t>(j) * c.n3 + k] - v, m.M - v, c.c[a]);
    }
    int32_t nv;
    if (glauber) {
      // Glauber dynamics: P(on) = 1/(1+exp(ΔE_on/T)).
      const double x = std::clamp(dE / temperature, -50.0, 50.0);
      nv = rng->uniform() * (1.0 + std::exp(x)) < 1.0 ? 1 : 0;
    } else {
      nv = dE < 0 ? 1 : (dE > 0 ? 0 : v);  // seed 000 Eq. 10
    }
    if (nv == v) continue;
    const int32_t d = nv - v;
    net.V[a] = static_cast<uint8_t>(nv);
    m.R[i] += d;
    m.S[j] += d;
    m.T[k] += d;
    m.M += d;
    if (printed) {
      m.Lij[ij] += d;
      m.Lik[static_cast<std::size_t>(i) * c.n3 + k] += d;
      m.Ljk[static_cast<std::size_t>(j) * c.n3 + k] += d;
    }
    net.hash ^= zobrist_key(a);
    ++flips;
  }
  return flips;
}

int64_t async_sweep_slices(DiscreteNetwork& net, std::span<const uint32_t> slice_order,
                           std::span<const uint32_t> packed_jk, std::span<const uint32_t> rotation) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = net.w;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  HopfieldMarginals& m = net.m;
  const std::size_t n2 = c.n2, n3 = c.n3, slice = n2 * n3;
  int32_t* __restrict S = m.S.data();
  int32_t* __restrict T = m.T.data();
  const float* __restrict cc = c.c.data();
  int64_t flips = 0;
  int64_t M = m.M;
  uint64_t hash = net.hash;
  for (uint32_t i : slice_order) {
    int32_t Ri = m.R[i];
    const std::size_t base = i * slice;
    uint8_t* __restrict V = net.V.data() + base;
    const std::size_t rot = rotation[i] % slice;
    for (std::size_t p = 0; p < slice; ++p) {
      std::size_t q = p + rot;
      if (q >= slice) q -= slice;
      const uint32_t jk = packed_jk[q];
      const std::size_t j = jk >> 16, k = jk & 0xffffu;
      const std::size_t off = j * n3 + k;
      const int32_t v = V[off];
      double dE;
      if (!printed) {
        dE = full_plane_delta_on(w, Ri - v, S[j] - v, T[k] - v, M - v, cc[base + off]);
      } else {
        dE = printed_delta_on(w, Ri - v, S[j] - v, T[k] - v, m.Lij[i * n2 + j] - v, m.Lik[i * n3 + k] - v,
                              m.Ljk[off] - v, M - v, cc[base + off]);
      }
      const int32_t nv = dE < 0 ? 1 : (dE > 0 ? 0 : v);  // seed 000 Eq. 10
      if (nv == v) continue;
      const int32_t d = nv - v;
      V[off] = static_cast<uint8_t>(nv);
      Ri += d;
      S[j] += d;
      T[k] += d;
      M += d;
      if (printed) {
        m.Lij[i * n2 + j] += d;
        m.Lik[i * n3 + k] += d;
        m.Ljk[off] += d;
      }
      hash ^= zobrist_key(base + off);
      ++flips;
    }
    m.R[i] = Ri;
  }
  m.M = M;
  net.hash = hash;
  return flips;
}

// ---------------------------------------------------------------------------------------------
// sync: Jacobi over i-slices.

namespace {

inline void atomic_add(int32_t& x, int32_t d) {
  if (d) std::atomic_ref<int32_t>(x).fetch_add(d, std::memory_order_relaxed);
}

}  // namespace

SyncSweepResult sync_sweep(DiscreteNetwork& net, double fraction, uint64_t sweep_key) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = net.w;
  const int32_t n1 = c.n1, n2 = c.n2, n3 = c.n3;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  const bool damped = fraction < 1.0;
  const uint64_t threshold = damped ? static_cast<uint64_t>(std::ldexp(std::max(fraction, 0.0), 64)) : ~0ULL;
  const HopfieldMarginals& old = net.m;
  HopfieldMarginals nw;
  nw.R.assign(n1, 0);
  nw.S.assign(n2, 0);
  nw.T.assign(n3, 0);
  if (printed) {
    nw.Lij.assign(static_cast<std::size_t>(n1) * n2, 0);
    nw.Lik.assign(static_cast<std::size_t>(n1) * n3, 0);
    nw.Ljk.assign(static_cast<std::size_t>(n2) * n3, 0);
  }
  // Per-k part of ΔE_on that does not depend on i, j.
  std::vector<float> tk(n3);
  for (int32_t k = 0; k < n3; ++k)
    tk[k] = printed ? 2.f * w.C * static_cast<float>(old.T[k]) : w.C * (static_cast<float>(old.T[k]) - 0.5f);
  const float Dterm = w.D * (static_cast<float>(old.M - w.N) + 0.5f);
  // Coefficient of the neuron's own state (primes exclude it).
  const float self = printed ? 2.f * (w.A + w.B + w.C) - w.D : -(w.A + w.B + w.C + w.D);
  const float E = w.E;
  std::atomic<int64_t> flips_total{0};
  std::atomic<uint64_t> hash_delta{0};
  int64_t M_new = 0;
  std::atomic<int64_t> M_acc{0};

  parallel_for_range(static_cast<std::size_t>(n1), 1, [&](std::size_t ib, std::size_t ie) {
    // Locals, not closure references: the uint8 stores below may alias anything reached through
    // a pointer, which would stop the vectoriser.
    const int32_t N2 = n2, N3 = n3;
    const float A = w.A, B = w.B, C2 = 2.f * w.C, Ef = E, self_c = self, Dt = Dterm;
    std::vector<int32_t> S_part(N2, 0), T_part(N3, 0),
        Ljk_part(printed ? static_cast<std::size_t>(N2) * N3 : 0, 0);
    std::vector<float> lik(printed ? N3 : 0);
    std::vector<uint8_t> nvbuf(N3);
    int64_t flips = 0, M_local = 0;
    uint64_t h = 0;
    for (std::size_t i = ib; i < ie; ++i) {
      if (printed)
        for (int32_t k = 0; k < N3; ++k) lik[k] = static_cast<float>(old.Lik[i * N3 + k]);
      int32_t R_new = 0;
      const float Ri = static_cast<float>(old.R[i]);
      for (int32_t j = 0; j < N2; ++j) {
        const std::size_t row = (i * N2 + j) * static_cast<std::size_t>(N3);
        uint8_t* __restrict V = net.V.data() + row;
        uint8_t* __restrict nv = nvbuf.data();
        const float* __restrict cc = c.c.data() + row;
        const float* __restrict t = tk.data();
        int32_t* __restrict Tp = T_part.data();
        int32_t changed = 0, Lij_new = 0;
        if (!printed) {
          const float base = A * (Ri - 0.5f) + B * (static_cast<float>(old.S[j]) - 0.5f) + Dt;
          for (int32_t k = 0; k < N3; ++k) {
            const uint8_t v = V[k];
            const float dE = base + t[k] + Ef * cc[k] + self_c * static_cast<float>(v);
            nv[k] = dE < 0.f ? 1 : (dE > 0.f ? 0 : v);
          }
          // Separate integer pass: one element type per loop lets GCC vectorise both.
          for (int32_t k = 0; k < N3; ++k) {
            changed += nv[k] ^ V[k];
            Lij_new += nv[k];
            Tp[k] += nv[k];
          }
        } else {
          const float Lij = static_cast<float>(old.Lij[i * N2 + j]);
          const float base = 2.f * A * (Ri - Lij) + 2.f * B * (static_cast<float>(old.S[j]) - Lij) + Dt;
          const int32_t* __restrict ljk = old.Ljk.data() + static_cast<std::size_t>(j) * N3;
          const float* __restrict l = lik.data();
          for (int32_t k = 0; k < N3; ++k) {
            const uint8_t v = V[k];
            const float Ljk = static_cast<float>(ljk[k]);
            const float dE = base - 2.f * A * l[k] - 2.f * B * Ljk + t[k] - C2 * (l[k] + Ljk) + Ef * cc[k] +
                             self_c * static_cast<float>(v);
            const uint8_t x = dE < 0.f ? 1 : (dE > 0.f ? 0 : v);
            nv[k] = x;
          }
          if (damped)
            for (int32_t k = 0; k < N3; ++k)
              if (splitmix64_mix(sweep_key ^ zobrist_key(row + k)) >= threshold) nv[k] = V[k];
          for (int32_t k = 0; k < N3; ++k) {
            changed += nv[k] ^ V[k];
            Lij_new += nv[k];
            Tp[k] += nv[k];
          }
        }
        if (damped && !printed) {
          // Undo the updates of the neurons this sweep leaves alone, then recount.
          changed = 0;
          Lij_new = 0;
          for (int32_t k = 0; k < N3; ++k) {
            Tp[k] -= nv[k];
            if (splitmix64_mix(sweep_key ^ zobrist_key(row + k)) >= threshold) nv[k] = V[k];
            changed += nv[k] ^ V[k];
            Lij_new += nv[k];
            Tp[k] += nv[k];
          }
        }
        if (changed) {
          for (int32_t k = 0; k < N3; ++k)
            if (nv[k] != V[k]) h ^= zobrist_key(row + k);
          flips += changed;
          std::memcpy(V, nv, N3);
        }
        if (printed) {
          nw.Lij[i * N2 + j] = Lij_new;
          int32_t* ljk_new = Ljk_part.data() + static_cast<std::size_t>(j) * N3;
          int32_t* lik_new = nw.Lik.data() + i * N3;
          for (int32_t k = 0; k < N3; ++k) {
            ljk_new[k] += nv[k];
            lik_new[k] += nv[k];
          }
        }
        S_part[j] += Lij_new;
        R_new += Lij_new;
      }
      nw.R[i] = R_new;
      M_local += R_new;
    }
    for (int32_t j = 0; j < N2; ++j) atomic_add(nw.S[j], S_part[j]);
    for (int32_t k = 0; k < N3; ++k) atomic_add(nw.T[k], T_part[k]);
    if (printed)
      for (std::size_t a = 0; a < Ljk_part.size(); ++a) atomic_add(nw.Ljk[a], Ljk_part[a]);
    flips_total.fetch_add(flips, std::memory_order_relaxed);
    hash_delta.fetch_xor(h, std::memory_order_relaxed);
    M_acc.fetch_add(M_local, std::memory_order_relaxed);
  });
  M_new = M_acc.load();
  nw.M = M_new;
  net.m = std::move(nw);
  net.hash ^= hash_delta.load();
  return {flips_total.load()};
}

// ---------------------------------------------------------------------------------------------
// diagonal: block-major layout, exact asynchronous semantics inside a block.

DiagonalNetwork::DiagonalNetwork(const HopfieldWeights& w, const NormalisedCost& c)
    : w_(w), n1_(c.n1), n2_(c.n2), n3_(c.n3) {
  require(n1_ <= n2_ && n1_ <= n3_, "schedule 'diagonal'", "needs n1 <= n2 and n1 <= n3");
  require(w.D == 0.f, "schedule 'diagonal'", "needs D = 0 (the D term couples every neuron)");
  c_.resize(c.size());
  V_.assign(c.size(), 0);
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b)
      for (int32_t i = 0; i < n1_; ++i)
        c_[(static_cast<std::size_t>(a) * n3_ + b) * n1_ + i] = c.c[standard_index(a, b, i)];
  R_.assign(n1_, 0.f);
  S_.assign(n2_, 0.f);
  T_.assign(n3_, 0.f);
}

std::size_t DiagonalNetwork::standard_index(int32_t a, int32_t b, int32_t i) const {
  const int32_t j = (i + a) % n2_, k = (i + b) % n3_;
  return (static_cast<std::size_t>(i) * n2_ + j) * n3_ + k;
}

void DiagonalNetwork::set_state(std::span<const uint8_t> V) {
  std::fill(R_.begin(), R_.end(), 0.f);
  std::fill(S_.begin(), S_.end(), 0.f);
  std::fill(T_.begin(), T_.end(), 0.f);
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b)
      for (int32_t i = 0; i < n1_; ++i) {
        const uint8_t v = V[standard_index(a, b, i)];
        V_[(static_cast<std::size_t>(a) * n3_ + b) * n1_ + i] = v;
        R_[i] += v;
        S_[(i + a) % n2_] += v;
        T_[(i + b) % n3_] += v;
      }
}

void DiagonalNetwork::get_state(std::span<uint8_t> V) const {
  for (int32_t a = 0; a < n2_; ++a)
    for (int32_t b = 0; b < n3_; ++b)
      for (int32_t i = 0; i < n1_; ++i)
        V[standard_index(a, b, i)] = V_[(static_cast<std::size_t>(a) * n3_ + b) * n1_ + i];
}

namespace {

// Updates the neurons i ∈ [lo, hi) of one block, where j = i + ja and k = i + kb (no wrap inside
// the segment). The n updates touch distinct R, S, T entries, so they vectorise.
inline int32_t update_segment(int32_t lo, int32_t hi, int32_t ja, int32_t kb, const float* __restrict c,
                              uint8_t* __restrict V, float* __restrict R, float* __restrict S,
                              float* __restrict T, float A, float B, float C, float E) {
  int32_t flips = 0;
  const float half = 0.5f * (A + B + C), self = A + B + C;
  for (int32_t i = lo; i < hi; ++i) {
    const float v = static_cast<float>(V[i]);
    // full-plane ΔE_on with primes: A(R−v−½) + B(S−v−½) + C(T−v−½) + E·ĉ
    const float dE = A * R[i] + B * S[i + ja] + C * T[i + kb] - self * v - half + E * c[i];
    const float nv = dE < 0.f ? 1.f : (dE > 0.f ? 0.f : v);
    const float d = nv - v;
    R[i] += d;
    S[i + ja] += d;
    T[i + kb] += d;
    V[i] = static_cast<uint8_t>(nv);
    flips += d != 0.f;
  }
  return flips;
}

}  // namespace

int64_t DiagonalNetwork::update_block(int32_t a, int32_t b) {
  const std::size_t base = (static_cast<std::size_t>(a) * n3_ + b) * n1_;
  const float* c = c_.data() + base;
  uint8_t* V = V_.data() + base;
  // Segment boundaries where j = i + a or k = i + b wraps.
  int32_t cuts[4] = {0, std::min(n1_, n2_ - a), std::min(n1_, n3_ - b), n1_};
  if (cuts[1] > cuts[2]) std::swap(cuts[1], cuts[2]);
  int64_t flips = 0;
  for (int s = 0; s < 3; ++s) {
    const int32_t lo = cuts[s], hi = cuts[s + 1];
    if (lo >= hi) continue;
    const int32_t ja = lo + a >= n2_ ? a - n2_ : a;
    const int32_t kb = lo + b >= n3_ ? b - n3_ : b;
    flips += update_segment(lo, hi, ja, kb, c, V, R_.data(), S_.data(), T_.data(), w_.A, w_.B, w_.C, w_.E);
  }
  return flips;
}

int64_t DiagonalNetwork::sweep(std::span<const uint32_t> block_order) {
  int64_t flips = 0;
  for (uint32_t blk : block_order)
    flips += update_block(static_cast<int32_t>(blk / n3_), static_cast<int32_t>(blk % n3_));
  return flips;
}

}  // namespace trackassoc
