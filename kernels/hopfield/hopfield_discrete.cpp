#include "kernels/hopfield/hopfield_discrete.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

DiscreteNetwork::DiscreteNetwork(HopfieldEnergy f, const HopfieldWeights& weights, const NormalisedCost& cost)
    : form(f), w(weights), c(&cost), V(cost.size(), 0) {
  m = compute_marginals(V, c->n1, c->n2, c->n3, form == HopfieldEnergy::kPrinted);
}

void DiscreteNetwork::set_state(std::span<const uint8_t> state) {
  V.resize(state.size());
  std::transform(state.begin(), state.end(), V.begin(), [](uint8_t v) -> uint8_t { return v != 0; });
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

// ΔE_on of neuron (i, j, k) with cost ca under both values of its own state: `off` for V = 0 (the
// marginals as they are) and `on` for V = 1 (its own contribution removed, the primes of
// kernels/hopfield/hopfield_energy.hpp). They are exactly the values the update computes for v = 0 and
// v = 1, so when off ≥ 0 and on ≤ 0 the rule of seed 000 Eq. 10 leaves the neuron as it is,
// whatever its state, and the state need not be read. In a near-valid state nearly every neuron
// is such a case (a neuron in three occupied planes cannot turn on; an active neuron alone in its
// planes cannot turn off), so a sweep streams its order and reads only the O(n) marginals.
struct DeltaPair {
  double off, on;
  // Written as a negation so that a NaN counts as "may flip" (the exact rule then decides).
  bool may_flip() const { return !(off >= 0.0 && on <= 0.0); }
};

inline DeltaPair delta_pair(const DiscreteNetwork& net, bool printed, int32_t i, int32_t j, int32_t k,
                            float ca) {
  const NormalisedCost& c = *net.c;
  const HopfieldWeights& w = net.w;
  const HopfieldMarginals& m = net.m;
  const int64_t R = m.R[i], S = m.S[j], T = m.T[k], M = m.M;
  if (!printed)
    return {full_plane_delta_on(w, R, S, T, M, ca), full_plane_delta_on(w, R - 1, S - 1, T - 1, M - 1, ca)};
  const int64_t Lij = m.Lij[static_cast<std::size_t>(i) * c.n2 + j],
                Lik = m.Lik[static_cast<std::size_t>(i) * c.n3 + k],
                Ljk = m.Ljk[static_cast<std::size_t>(j) * c.n3 + k];
  return {printed_delta_on(w, R, S, T, Lij, Lik, Ljk, M, ca),
          printed_delta_on(w, R - 1, S - 1, T - 1, Lij - 1, Lik - 1, Ljk - 1, M - 1, ca)};
}

// A cheap conservative pre-test ahead of the exact pair, for the async sweeps at T = 0. Whatever
// the energy, off(ĉ) = base + E·ĉ and on(ĉ) = off(ĉ) − shift with a state-dependent base:
//   full plane: base = A·R + B·S + C·T + D·M − (A+B+C)/2 + D(½ − N), shift = A + B + C + D;
//   printed:    base = 2A(R−Lij−Lik) + 2B(S−Lij−Ljk) + 2C(T−Lik−Ljk) + D(M − N + ½),
//               shift = D − 2(A+B+C) (the line sums cancel part of the plane sums).
// It is evaluated in another order than the exact pair, so a decision needs the margin `margin`,
// which bounds the rounding of both evaluations: 10⁻¹³ of the largest magnitude any term can take
// (|A|+|B|+|C|+|D| times 4(K + N + 2), plus 2|E|·max|ĉ|), some 400 ulps of it. Unknown cost
// bounds (±inf) make every test undecided, so the exact rule runs.
struct NoFlipFilter {
  double A, B, C, D, E, k, shift, margin;
  bool printed;
  NoFlipFilter(const DiscreteNetwork& net) {
    const HopfieldWeights& w = net.w;
    A = w.A, B = w.B, C = w.C, D = w.D, E = w.E;
    printed = net.form == HopfieldEnergy::kPrinted;
    k = printed ? D * (0.5 - w.N) : -0.5 * (A + B + C) + D * (0.5 - w.N);
    shift = printed ? D - 2.0 * (A + B + C) : A + B + C + D;
    const double cmax = std::max(
        {std::abs(static_cast<double>(net.c->c_lo)), std::abs(static_cast<double>(net.c->c_hi)), 1.0});
    margin = 1e-13 * ((std::abs(A) + std::abs(B) + std::abs(C) + std::abs(D)) * 4.0 *
                          (static_cast<double>(net.c->size()) + std::abs(static_cast<double>(w.N)) + 2.0) +
                      2.0 * std::abs(E) * cmax);
  }
  double base(const DiscreteNetwork& net, int32_t i, int32_t j, int32_t kk) const {
    const HopfieldMarginals& m = net.m;
    if (!printed) return A * m.R[i] + B * m.S[j] + C * m.T[kk] + D * static_cast<double>(m.M) + k;
    const NormalisedCost& c = *net.c;
    const double Lij = m.Lij[static_cast<std::size_t>(i) * c.n2 + j],
                 Lik = m.Lik[static_cast<std::size_t>(i) * c.n3 + kk],
                 Ljk = m.Ljk[static_cast<std::size_t>(j) * c.n3 + kk];
    return 2.0 * A * (m.R[i] - Lij - Lik) + 2.0 * B * (m.S[j] - Lij - Ljk) + 2.0 * C * (m.T[kk] - Lik - Ljk) +
           D * static_cast<double>(m.M) + k;
  }
  // Given off ≥ off_min and on ≤ on_max for this neuron's cost: kStays (no flip, whatever the
  // state), kStaysIfOff (cannot turn on: only an active neuron may flip) or kUndecided.
  enum Verdict { kStays, kStaysIfOff, kUndecided };
  Verdict verdict(double off_min, double on_max) const {
    if (!(off_min >= margin)) return kUndecided;
    return on_max <= -margin ? kStays : kStaysIfOff;
  }
};

// The state as one bit per neuron, built at the start of a sweep and kept in step with V by
// apply_update: the async orders read the state at random, and K/8 bytes stay in L2 where the K
// bytes of V do not (n = 100: 125 KB against 1 MB).
class StateBits {
 public:
  explicit StateBits(std::span<const uint8_t> V) : w_((V.size() + 63) / 64, 0) {
    const std::size_t K = V.size(), full = K / 8;
    for (std::size_t q = 0; q < full; ++q) {
      uint64_t x;
      std::memcpy(&x, V.data() + 8 * q, 8);
      // Bytes are 0/1 (set_state): the product gathers byte t's bit 0 into bit 56 + t, and the
      // partial products never overlap, so no carry disturbs the top byte.
      w_[q / 8] |= ((x * 0x0102040810204080ULL) >> 56) << (8 * (q % 8));
    }
    for (std::size_t a = 8 * full; a < K; ++a) w_[a / 64] |= static_cast<uint64_t>(V[a] != 0) << (a % 64);
  }
  bool get(std::size_t a) const { return (w_[a / 64] >> (a % 64)) & 1u; }
  void flip(std::size_t a) { w_[a / 64] ^= uint64_t{1} << (a % 64); }

 private:
  std::vector<uint64_t> w_;
};

// Applies the rule of seed 000 Eq. 10 (or Glauber's at temperature T > 0) to neuron a = (i, j, k)
// given its ΔE pair, then updates the state (V and its bits), the marginals and the hash. Returns
// 1 on a flip.
inline int64_t apply_update(DiscreteNetwork& net, StateBits& bits, bool printed, uint32_t a, int32_t i,
                            int32_t j, int32_t k, const DeltaPair& d, double temperature, CounterRng* rng) {
  const NormalisedCost& c = *net.c;
  HopfieldMarginals& m = net.m;
  const int32_t v = bits.get(a);
  const double dE = v ? d.on : d.off;
  int32_t nv;
  if (temperature > 0.0) {
    // Glauber dynamics: P(on) = 1/(1+exp(ΔE_on/T)).
    const double x = std::clamp(dE / temperature, -50.0, 50.0);
    nv = rng->uniform() * (1.0 + std::exp(x)) < 1.0 ? 1 : 0;
  } else {
    nv = dE < 0 ? 1 : (dE > 0 ? 0 : v);  // seed 000 Eq. 10
  }
  if (nv == v) return 0;
  const int32_t dv = nv - v;
  net.V[a] = static_cast<uint8_t>(nv);
  bits.flip(a);
  m.R[i] += dv;
  m.S[j] += dv;
  m.T[k] += dv;
  m.M += dv;
  if (printed) {
    m.Lij[static_cast<std::size_t>(i) * c.n2 + j] += dv;
    m.Lik[static_cast<std::size_t>(i) * c.n3 + k] += dv;
    m.Ljk[static_cast<std::size_t>(j) * c.n3 + k] += dv;
  }
  net.hash ^= zobrist_key(a);
  return 1;
}

}  // namespace

int64_t async_sweep(DiscreteNetwork& net, std::span<const uint32_t> order, double temperature,
                    CounterRng* rng) {
  const NormalisedCost& c = *net.c;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  const double T = temperature > 0.0 && rng != nullptr ? temperature : 0.0;
  const NeuronIndexer index(c);
  // At T = 0 the filter at the ends of [c_lo, c_hi] (NormalisedCost) bounds the pair at the
  // neuron's own cost (E·ĉ is its only ĉ term), so most neurons are settled without reading their
  // cost or state, both at random addresses in this order. The rest take the exact update.
  const NoFlipFilter filter(net);
  const bool E_nonneg = net.w.E >= 0.f;
  const double Ec_small = filter.E * (E_nonneg ? c.c_lo : c.c_hi),
               Ec_large = filter.E * (E_nonneg ? c.c_hi : c.c_lo);
  StateBits bits(net.V);
  int64_t flips = 0;
  for (uint32_t a : order) {
    const auto [i, j, k] = index(a);
    if (T == 0.0) {
      const double base = filter.base(net, i, j, k);
      const auto v = filter.verdict(base + Ec_small, base - filter.shift + Ec_large);
      if (v == NoFlipFilter::kStays || (v == NoFlipFilter::kStaysIfOff && !bits.get(a))) continue;
    }
    const DeltaPair d = delta_pair(net, printed, i, j, k, c.c[a]);
    if (T == 0.0 && !d.may_flip()) continue;
    flips += apply_update(net, bits, printed, a, i, j, k, d, T, rng);
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
  const NeuronIndexer index(c);
  parallel_for_range(order.size(), 65536, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t p = lo; p < hi; ++p) {
      const uint32_t a = order[p];
      if (a >= c.size()) throw InputError("async order: neuron index out of range");
      const auto [ii, jj, kk] = index(a);
      i[p] = static_cast<uint16_t>(ii);
      j[p] = static_cast<uint16_t>(jj);
      k[p] = static_cast<uint16_t>(kk);
      cost[p] = c.c[a];
    }
  });
}

int64_t async_sweep_planned(DiscreteNetwork& net, const OrderedSweepPlan& plan) {
  const std::size_t K = plan.neuron.size();
  const uint32_t* neuron = plan.neuron.data();
  int64_t flips = 0;
  const bool printed = net.form == HopfieldEnergy::kPrinted;
  StateBits bits(net.V);
  const NoFlipFilter filter(net);
  for (std::size_t p = 0; p < K; ++p) {
    const double base = filter.base(net, plan.i[p], plan.j[p], plan.k[p]), Ec = filter.E * plan.cost[p];
    const auto v = filter.verdict(base + Ec, base - filter.shift + Ec);
    if (v == NoFlipFilter::kStays || (v == NoFlipFilter::kStaysIfOff && !bits.get(neuron[p]))) continue;
    const DeltaPair d = delta_pair(net, printed, plan.i[p], plan.j[p], plan.k[p], plan.cost[p]);
    if (!d.may_flip()) continue;  // stays whatever its state: the state is not read
    flips += apply_update(net, bits, printed, neuron[p], plan.i[p], plan.j[p], plan.k[p], d, 0.0, nullptr);
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
