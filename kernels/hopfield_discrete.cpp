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

namespace {

// One Gauss–Seidel update of neuron a = (i, j, k) with normalised cost ca: the exact ΔE_on from
// the marginals (primes exclude the neuron), the rule of seed 000 Eq. 10 (or Glauber's at
// temperature T > 0), then the marginals and the hash. Returns 1 on a flip.
inline int64_t update_neuron(DiscreteNetwork& net, uint32_t a, int32_t i, int32_t j, int32_t k, float ca,
                             double temperature, CounterRng* rng) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = net.w;
  HopfieldMarginals& m = net.m;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  const std::size_t ij = static_cast<std::size_t>(i) * c.n2 + j, ik = static_cast<std::size_t>(i) * c.n3 + k,
                    jk = static_cast<std::size_t>(j) * c.n3 + k;
  const int32_t v = net.V[a];
  double dE;
  if (!printed) {
    dE = full_plane_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v, m.M - v, ca);
  } else {
    dE = printed_delta_on(w, m.R[i] - v, m.S[j] - v, m.T[k] - v, m.Lij[ij] - v, m.Lik[ik] - v, m.Ljk[jk] - v,
                          m.M - v, ca);
  }
  int32_t nv;
  if (temperature > 0.0) {
    // Glauber dynamics: P(on) = 1/(1+exp(ΔE_on/T)).
    const double x = std::clamp(dE / temperature, -50.0, 50.0);
    nv = rng->uniform() * (1.0 + std::exp(x)) < 1.0 ? 1 : 0;
  } else {
    nv = dE < 0 ? 1 : (dE > 0 ? 0 : v);  // seed 000 Eq. 10
  }
  if (nv == v) return 0;
  const int32_t d = nv - v;
  net.V[a] = static_cast<uint8_t>(nv);
  m.R[i] += d;
  m.S[j] += d;
  m.T[k] += d;
  m.M += d;
  if (printed) {
    m.Lij[ij] += d;
    m.Lik[ik] += d;
    m.Ljk[jk] += d;
  }
  net.hash ^= zobrist_key(a);
  return 1;
}

}  // namespace

int64_t async_sweep(DiscreteNetwork& net, std::span<const uint32_t> order, double temperature,
                    CounterRng* rng) {
  const NormalisedCost& c = *net.c;
  const double T = temperature > 0.0 && rng != nullptr ? temperature : 0.0;
  const FastDivider div3(static_cast<uint32_t>(c.n3)), div2(static_cast<uint32_t>(c.n2));
  int64_t flips = 0;
  for (uint32_t a : order) {
    const uint32_t ij = div3.div(a);
    const int32_t k = static_cast<int32_t>(a - ij * static_cast<uint32_t>(c.n3));
    const int32_t i = static_cast<int32_t>(div2.div(ij));
    const int32_t j = static_cast<int32_t>(ij - static_cast<uint32_t>(i) * c.n2);
    flips += update_neuron(net, a, i, j, k, c.c[a], T, rng);
  }
  return flips;
}

OrderedSweepPlan::OrderedSweepPlan(std::span<const uint32_t> order, const NormalisedCost& c)
    : neuron(order.begin(), order.end()),
      i(order.size()),
      j(order.size()),
      k(order.size()),
      cost(order.size()) {
  require(c.n1 < 65536 && c.n2 < 65536 && c.n3 < 65536, "async order", "needs n1, n2, n3 < 65536");
  const FastDivider div3(static_cast<uint32_t>(c.n3)), div2(static_cast<uint32_t>(c.n2));
  parallel_for_range(order.size(), 65536, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t p = lo; p < hi; ++p) {
      const uint32_t a = order[p];
      if (a >= c.size()) throw InputError("async order: neuron index out of range");
      const uint32_t ij = div3.div(a), ii = div2.div(ij);
      i[p] = static_cast<uint16_t>(ii);
      j[p] = static_cast<uint16_t>(ij - ii * static_cast<uint32_t>(c.n2));
      k[p] = static_cast<uint16_t>(a - ij * static_cast<uint32_t>(c.n3));
      cost[p] = c.c[a];
    }
  });
}

int64_t async_sweep_planned(DiscreteNetwork& net, const OrderedSweepPlan& plan) {
  const std::size_t K = plan.neuron.size();
  const uint32_t* neuron = plan.neuron.data();
  constexpr std::size_t kAhead = 32;  // the state is read at random: prefetch it
  int64_t flips = 0;
  for (std::size_t p = 0; p < K; ++p) {
    if (p + kAhead < K) __builtin_prefetch(net.V.data() + neuron[p + kAhead], 1);
    flips += update_neuron(net, neuron[p], plan.i[p], plan.j[p], plan.k[p], plan.cost[p], 0.0, nullptr);
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

}  // namespace trackassoc
