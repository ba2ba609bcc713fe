// Energies of the 3-D Hopfield network for the axial 3-D assignment (seed 000 §3.1; docs/design.md §4.4).
//
// Neuron V_ijk ∈ {0, 1} (uint8) means "tracks i, j, k (one per sensor) are the same target".
// Every update reads O(1) marginal sums instead of an n⁶ weight matrix:
//   plane sums R_i = Σ_jk V_ijk, S_j = Σ_ik V_ijk, T_k = Σ_ij V_ijk, M = Σ V;
//   line sums  L_ij = Σ_k V_ijk, L_ik = Σ_j V_ijk, L_jk = Σ_i V_ijk (printed energy only).
//
// Full-plane energy (the default; ĉ = cost normalised to [0, 1], see normalise_cost):
//   E = A/2·Σ_i(R_i−1)² + B/2·Σ_j(S_j−1)² + C/2·Σ_k(T_k−1)² + D/2·(M−N)² + E·Σ ĉ_ijk V_ijk
// Turning V_ijk on changes it by (primes exclude the neuron itself)
//   ΔE_on = A(R'_i−½) + B(S'_j−½) + C(T'_k−½) + D(M'−N+½) + E·ĉ_ijk,
// and turning it off by −ΔE_on. Consequence: with E·ĉ_max < (A+B+C+D)/2 every valid assignment
// (a permutation when n1 = n2 = n3 = N) is a fixed point of the discrete network.
//
// Printed energy (seed 000 Eq. 11, taken literally, with 0/1 states):
//   E = A·Σ_ijk Σ_{y≠j} Σ_{z≠k} V_ijk V_iyz + B·Σ_ijk Σ_{x≠i} Σ_{z≠k} V_ijk V_xjz
//     + C·Σ_ijk Σ_{x≠i} Σ_{y≠j} V_ijk V_xyk + D/2·(M−N)² + E·Σ ĉ_ijk V_ijk
// By inclusion–exclusion Σ_{y≠j,z≠k} V_iyz = R_i − L_ij − L_ik + V_ijk, so
//   ΔE_on = 2A(R'_i−L'_ij−L'_ik) + 2B(S'_j−L'_ij−L'_jk) + 2C(T'_k−L'_ik−L'_jk) + D(M'−N+½) + E·ĉ_ijk.
// Errata of the paper (docs/design.md §4.4), as implemented here:
//   - two neurons on the same line (same i and j, different k) are not penalised by Eq. 11;
//   - θ_ijk = D·N − E·b_ijk of Eq. 12 has the sign that favours high cost: from Eq. 11 it is
//     θ = D(½−N) + E·ĉ (the ½ is the self-coupling of the D term for 0/1 states);
//   - Eq. 12's weights −Aδ(i,x)(1−δ(j,y))(1−δ(k,z)) equal −½ of Eq. 11's ordered-pair factor
//     (Eq. 9 has the usual ½), so Eq. 11 read literally gives −2A; we keep Eq. 11;
//   - Eq. 8 uses ±1 states, but the energy is a 0/1 assignment energy: states are 0/1.
//
// The naive reference (NaiveHopfieldNetwork) builds the full (n1n2n3)² weight matrix of the
// Eq. 9 form E = −½ΣΣ V W V + Σ θ V + const; it is used only by tests and one benchmark.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class HopfieldEnergy { kFullPlane, kPrinted };
inline constexpr EnumName<HopfieldEnergy> kHopfieldEnergyNames[]{{HopfieldEnergy::kFullPlane, "full_plane"},
                                                                 {HopfieldEnergy::kPrinted, "printed"}};
constexpr std::span<const EnumName<HopfieldEnergy>> enum_names(HopfieldEnergy) {
  return kHopfieldEnergyNames;
}

// Penalty coefficients of either energy. N is the target number of active neurons
// (min(n1, n2, n3) for an assignment).
struct HopfieldWeights {
  float A = 1.f, B = 1.f, C = 1.f, D = 0.f, E = 1.f;
  int32_t N = 0;
};

// ĉ_ijk = (b_ijk − b_min) / (b_max − b_min) over the finite entries; +inf entries (forbidden
// tuples) map to 1 + `inf_margin`, so they are never preferred. A constant tensor maps to 0.
struct NormalisedCost {
  int32_t n1 = 0, n2 = 0, n3 = 0;
  std::vector<float> c;  // ĉ, same layout as CostTensor3::cost
  float b_min = 0.f, b_range = 1.f;
  // Bounds on every ĉ (c_lo ≤ ĉ ≤ c_hi), for the sweeps' no-flip test; ±inf (the default) means
  // "unknown" and disables that test, so a hand-filled NormalisedCost stays correct.
  float c_lo = -std::numeric_limits<float>::infinity(), c_hi = std::numeric_limits<float>::infinity();
  std::size_t size() const { return c.size(); }
};
NormalisedCost normalise_cost(const CostTensor3& cost, float inf_margin = 1.f);

// Division by a run-time constant through a double reciprocal with an exact correction
// (dividends < 2^32), about 5× faster than an integer division in the random-order inner loops.
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

// Neuron a = (i·n2 + j)·n3 + k back to (i, j, k), for the sweeps that visit neurons in an
// arbitrary order (K < 2^32).
struct NeuronIndexer {
  FastDivider div3, div2;
  int32_t n2, n3;
  explicit NeuronIndexer(const NormalisedCost& c)
      : div3(static_cast<uint32_t>(c.n3)), div2(static_cast<uint32_t>(c.n2)), n2(c.n2), n3(c.n3) {}
  struct Ijk {
    int32_t i, j, k;
  };
  Ijk operator()(uint32_t a) const {
    const uint32_t ij = div3.div(a), i = div2.div(ij);
    return {static_cast<int32_t>(i), static_cast<int32_t>(ij - i * static_cast<uint32_t>(n2)),
            static_cast<int32_t>(a - ij * static_cast<uint32_t>(n3))};
  }
};

// Marginal sums of a 0/1 state. Line sums are filled only when `lines` is true.
struct HopfieldMarginals {
  std::vector<int32_t> R, S, T;        // plane sums
  std::vector<int32_t> Lij, Lik, Ljk;  // line sums: Lij[i·n2+j], Lik[i·n3+k], Ljk[j·n3+k]
  int64_t M = 0;
};
HopfieldMarginals compute_marginals(std::span<const uint8_t> V, int32_t n1, int32_t n2, int32_t n3,
                                    bool lines);

// The energy of a 0/1 state, evaluated from the marginals in O(n1n2n3). Double accumulation.
double hopfield_energy(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c,
                       std::span<const uint8_t> V);

// ΔE of turning neuron (i, j, k) on, from the marginals with the neuron itself excluded.
inline double full_plane_delta_on(const HopfieldWeights& w, int64_t Ri, int64_t Sj, int64_t Tk, int64_t M,
                                  float c) {
  return w.A * (Ri - 0.5) + w.B * (Sj - 0.5) + w.C * (Tk - 0.5) + w.D * (M - w.N + 0.5) +
         static_cast<double>(w.E) * c;
}
inline double printed_delta_on(const HopfieldWeights& w, int64_t Ri, int64_t Sj, int64_t Tk, int64_t Lij,
                               int64_t Lik, int64_t Ljk, int64_t M, float c) {
  return 2.0 * w.A * (Ri - Lij - Lik) + 2.0 * w.B * (Sj - Lij - Ljk) + 2.0 * w.C * (Tk - Lik - Ljk) +
         w.D * (M - w.N + 0.5) + static_cast<double>(w.E) * c;
}

// ΔE_on of neuron (i, j, k) in state V with marginals m (the neuron's own contribution is
// removed here). O(1).
double delta_on(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c,
                const HopfieldMarginals& m, std::span<const uint8_t> V, int32_t i, int32_t j, int32_t k);

// Largest E for which every valid assignment is a fixed point (ĉ_max = 1 after normalisation):
//   full plane: E·ĉ_max < (A+B+C+D)/2 (docs/design.md §4.4);
//   printed:    E·ĉ_max < D/2 (an active neuron of a valid state has no plane or line partner, so
//               only the D term keeps it on; without D every neuron switches off).
inline double fixed_point_E_bound(const HopfieldWeights& w) { return 0.5 * (w.A + w.B + w.C + w.D); }
inline double fixed_point_E_bound(HopfieldEnergy form, const HopfieldWeights& w) {
  return form == HopfieldEnergy::kFullPlane ? fixed_point_E_bound(w) : 0.5 * w.D;
}

// Naive reference: the explicit weights W (K×K, K = n1n2n3, zero diagonal) and thresholds θ of
// E = −½ Σ_ab V_a W_ab V_b + Σ_a θ_a V_a + const. O(K²) memory: tests and one benchmark only.
class NaiveHopfieldNetwork {
 public:
  NaiveHopfieldNetwork(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c);
  std::size_t size() const { return theta_.size(); }
  // net_a = Σ_b W_ab V_b − θ_a = −ΔE_on(a) (seed 000 Eq. 10).
  double net_input(std::span<const uint8_t> V, std::size_t a) const;
  double energy(std::span<const uint8_t> V) const;
  // One synchronous (Jacobi) sweep of the rule V ← [net > 0], unchanged at net = 0.
  void sync_sweep(std::span<const uint8_t> V, std::span<uint8_t> out) const;
  // One asynchronous sweep in the given order, in place.
  void async_sweep(std::span<uint8_t> V, std::span<const uint32_t> order) const;

 private:
  std::vector<float> W_;
  std::vector<double> theta_;
  double constant_ = 0.0;
};

}  // namespace trackassoc
