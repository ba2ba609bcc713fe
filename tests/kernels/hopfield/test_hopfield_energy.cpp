// Invariants of the Hopfield energies and sweeps (kernels/hopfield/hopfield_energy.hpp,
// kernels/hopfield/hopfield_discrete.hpp), checked against brute-force energies and the naive n⁶-weight
// reference network.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>

#include "kernels/core/error.hpp"
#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "kernels/hopfield/hopfield_diagonal.hpp"
#include "kernels/hopfield/hopfield_discrete.hpp"
#include "kernels/hopfield/hopfield_energy.hpp"
#include "tests/support/hopfield_test_support.hpp"

namespace trackassoc {
namespace {

using namespace hopfield_test;

const Dims kDims[] = {{3, 3, 3}, {4, 4, 4}, {3, 4, 5}, {5, 4, 3}, {2, 6, 4}};
const HopfieldEnergy kForms[] = {HopfieldEnergy::kFullPlane, HopfieldEnergy::kPrinted};

// The incrementally kept marginals of a network equal those recomputed from its state.
void expect_marginals_recomputed(const DiscreteNetwork& net) {
  const NormalisedCost& c = *net.c;
  const HopfieldMarginals m =
      compute_marginals(net.V, c.n1, c.n2, c.n3, net.form == HopfieldEnergy::kPrinted);
  EXPECT_EQ(m.R, net.m.R);
  EXPECT_EQ(m.S, net.m.S);
  EXPECT_EQ(m.T, net.m.T);
  EXPECT_EQ(m.Lij, net.m.Lij);
  EXPECT_EQ(m.Lik, net.m.Lik);
  EXPECT_EQ(m.Ljk, net.m.Ljk);
  EXPECT_EQ(m.M, net.m.M);
}

TEST(HopfieldEnergy, NormalisedCostSpansUnitInterval) {
  CostTensor3 t(2, 2, 2);
  t.cost = {3, 5, 7, 11, 3, 3, std::numeric_limits<float>::infinity(), 5};
  const NormalisedCost c = normalise_cost(t);
  EXPECT_FLOAT_EQ(c.c[0], 0.f);
  EXPECT_FLOAT_EQ(c.c[1], 0.25f);
  EXPECT_FLOAT_EQ(c.c[3], 1.f);
  EXPECT_FLOAT_EQ(c.c[6], 2.f);  // +inf → 1 + margin
}

TEST(HopfieldEnergy, HandComputedFullPlaneAndPrinted) {
  // 2×2×2, state with V_000 = V_001 = 1 (two neurons on one line i=0, j=0), ĉ_000 = 0, ĉ_001 = 1/3.
  CostTensor3 t(2, 2, 2);
  t.cost = {0, 1, 2, 3, 3, 3, 3, 3};
  const NormalisedCost c = normalise_cost(t);
  std::vector<uint8_t> V = {1, 1, 0, 0, 0, 0, 0, 0};
  HopfieldWeights w{1, 2, 3, 4, 6, 2};
  // R = (2, 0), S = (2, 0), T = (1, 1), M = 2:
  // A/2·(1+1) + B/2·(1+1) + C/2·0 + D/2·0 + E·(0 + 1/3) = 1 + 2 + 2 = 5.
  EXPECT_NEAR(hopfield_energy(HopfieldEnergy::kFullPlane, w, c, V), 5.0, 1e-6);
  // Printed: the A and B terms ignore the same-line pair (erratum); C: different k. E term = 2.
  EXPECT_NEAR(hopfield_energy(HopfieldEnergy::kPrinted, w, c, V), 2.0, 1e-6);
  // Two neurons (0,0,0), (0,1,1) in plane i=0 on different lines: A counts both ordered pairs.
  std::vector<uint8_t> V2 = {1, 0, 0, 1, 0, 0, 0, 0};
  // ĉ_011 = 1: A·2 + E·(0 + 1) = 2 + 6.
  EXPECT_NEAR(hopfield_energy(HopfieldEnergy::kPrinted, w, c, V2), 8.0, 1e-6);
}

TEST(HopfieldEnergy, IncrementalDeltaEqualsBruteForceDifference) {
  CounterRng rng(7, 2);
  for (const auto& d : kDims)
    for (HopfieldEnergy form : kForms)
      for (int trial = 0; trial < 3; ++trial) {
        const CostTensor3 t = random_tensor(d.n1, d.n2, d.n3, 100 + trial);
        const NormalisedCost c = normalise_cost(t);
        const HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
        std::vector<uint8_t> V = random_state(c.size(), 0.3, rng);
        const HopfieldMarginals m = compute_marginals(V, d.n1, d.n2, d.n3, true);
        const double E0 = hopfield_energy(form, w, c, V);
        for (int32_t i = 0; i < d.n1; ++i)
          for (int32_t j = 0; j < d.n2; ++j)
            for (int32_t k = 0; k < d.n3; ++k) {
              const std::size_t a = (static_cast<std::size_t>(i) * d.n2 + j) * d.n3 + k;
              const double don = delta_on(form, w, c, m, V, i, j, k);
              std::vector<uint8_t> W = V;
              W[a] = 1;
              const double Eon = hopfield_energy(form, w, c, W);
              W[a] = 0;
              const double Eoff = hopfield_energy(form, w, c, W);
              ASSERT_NEAR(Eon - Eoff, don, 1e-4 * (1 + std::abs(don))) << enum_name(form);
              (void)E0;
            }
      }
}

TEST(HopfieldEnergy, NaiveWeightsReproduceEnergyAndNetInput) {
  CounterRng rng(8, 2);
  for (const auto& d : kDims)
    for (HopfieldEnergy form : kForms) {
      const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 5));
      const HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
      const NaiveHopfieldNetwork naive(form, w, c);
      for (int trial = 0; trial < 4; ++trial) {
        const std::vector<uint8_t> V = random_state(c.size(), 0.25, rng);
        EXPECT_NEAR(naive.energy(V), hopfield_energy(form, w, c, V), 1e-3);
        DiscreteNetwork net(form, w, c);
        net.set_state(V);
        for (std::size_t a = 0; a < c.size(); ++a) ASSERT_NEAR(naive.net_input(V, a), -net.delta_on(a), 1e-4);
      }
    }
}

// Every single asynchronous flip never raises the energy (seed 000 Eq. 14), for both energies.
TEST(HopfieldDiscrete, AsyncFlipNeverRaisesEnergy) {
  CounterRng rng(9, 2);
  for (const auto& d : kDims)
    for (HopfieldEnergy form : kForms)
      for (int trial = 0; trial < 3; ++trial) {
        const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 200 + trial));
        const HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
        DiscreteNetwork net(form, w, c);
        net.set_state(random_state(c.size(), 0.4, rng));
        std::vector<uint32_t> order(c.size());
        std::iota(order.begin(), order.end(), 0u);
        double E = net.energy();
        int64_t flips = 0;
        for (int sweep = 0; sweep < 6; ++sweep) {
          rng.shuffle(std::span<uint32_t>(order));
          for (uint32_t a : order) {
            flips += async_sweep(net, std::span<const uint32_t>(&a, 1));
            const double E1 = net.energy();
            ASSERT_LE(E1, E + 1e-6) << enum_name(form) << " sweep " << sweep;
            E = E1;
          }
        }
        EXPECT_GT(flips, 0);
        // The incrementally kept marginals equal recomputed ones.
        expect_marginals_recomputed(net);
      }
}

// The marginal-sum sweeps equal the naive weight-matrix network, sweep by sweep.
TEST(HopfieldDiscrete, MarginalSweepsEqualNaiveReference) {
  CounterRng rng(10, 2);
  for (const auto& d : kDims)
    for (HopfieldEnergy form : kForms)
      for (int trial = 0; trial < 3; ++trial) {
        const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 300 + trial));
        const HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
        const NaiveHopfieldNetwork naive(form, w, c);
        const std::vector<uint8_t> V0 = random_state(c.size(), 0.3, rng);
        // sync
        DiscreteNetwork net(form, w, c);
        net.set_state(V0);
        std::vector<uint8_t> ref = V0, next(c.size());
        for (int s = 0; s < 5; ++s) {
          naive.sync_sweep(ref, next);
          ref = next;
          sync_sweep(net, 1.0, 0);
          ASSERT_EQ(net.V, ref) << "sync sweep " << s << " " << enum_name(form);
        }
        expect_marginals_recomputed(net);
        // async in the same random order
        net.set_state(V0);
        ref = V0;
        std::vector<uint32_t> order(c.size());
        std::iota(order.begin(), order.end(), 0u);
        for (int s = 0; s < 4; ++s) {
          rng.shuffle(std::span<uint32_t>(order));
          naive.async_sweep(ref, order);
          async_sweep(net, order);
          ASSERT_EQ(net.V, ref) << "async sweep " << s << " " << enum_name(form);
        }
      }
}

// The slice-ordered async kernel equals the naive network visiting the same neurons in the same
// order (the order spelled out explicitly).
TEST(HopfieldDiscrete, SliceAsyncEqualsNaiveInTheSameOrder) {
  CounterRng rng(13, 2);
  for (const auto& d : kDims)
    for (HopfieldEnergy form : kForms) {
      const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 600));
      const HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
      const NaiveHopfieldNetwork naive(form, w, c);
      std::vector<uint8_t> ref = random_state(c.size(), 0.3, rng);
      DiscreteNetwork net(form, w, c);
      net.set_state(ref);
      std::vector<uint32_t> slices(d.n1), packed, rotation(d.n1);
      std::iota(slices.begin(), slices.end(), 0u);
      for (int32_t j = 0; j < d.n2; ++j)
        for (int32_t k = 0; k < d.n3; ++k) packed.push_back(static_cast<uint32_t>(j) << 16 | k);
      const std::size_t slice = packed.size();
      for (int s = 0; s < 4; ++s) {
        rng.shuffle(std::span<uint32_t>(slices));
        rng.shuffle(std::span<uint32_t>(packed));
        for (auto& r : rotation) r = static_cast<uint32_t>(rng.uniform_int(slice));
        std::vector<uint32_t> order;
        for (uint32_t i : slices)
          for (std::size_t p = 0; p < slice; ++p) {
            const uint32_t jk = packed[(p + rotation[i]) % slice];
            order.push_back(static_cast<uint32_t>((i * d.n2 + (jk >> 16)) * d.n3 + (jk & 0xffff)));
          }
        naive.async_sweep(ref, order);
        async_sweep_slices(net, slices, packed, rotation);
        ASSERT_EQ(net.V, ref) << enum_name(form) << " sweep " << s;
      }
      expect_marginals_recomputed(net);
    }
}

// The async kernels skip a neuron without reading its state when its ΔE pair (state off / on)
// proves it stays, and async_sweep also without reading its cost when the pair at the cost bounds
// [c_lo, c_hi] proves it. This checks both against a reference that reads every neuron and
// re-derives the marginals after every flip: identical states and flip counts, sweep by sweep.
// The cases are the ones the skip is built for and the ones that break a careless bound: near-valid
// states (a permutation with neurons removed and added), forbidden (+inf) tuples that put c_hi at
// 1 + margin, a negative E (the cost bounds swap), and both energies.
int64_t reference_async_sweep(HopfieldEnergy form, const HopfieldWeights& w, const NormalisedCost& c,
                              std::vector<uint8_t>& V, std::span<const uint32_t> order) {
  const bool printed = form == HopfieldEnergy::kPrinted;
  HopfieldMarginals m = compute_marginals(V, c.n1, c.n2, c.n3, printed);
  int64_t flips = 0;
  for (uint32_t a : order) {
    const int32_t k = static_cast<int32_t>(a % c.n3), j = static_cast<int32_t>(a / c.n3 % c.n2),
                  i = static_cast<int32_t>(a / c.n3 / c.n2);
    const double dE = delta_on(form, w, c, m, V, i, j, k);
    const uint8_t nv = dE < 0 ? 1 : (dE > 0 ? 0 : V[a]);
    if (nv == V[a]) continue;
    V[a] = nv;
    ++flips;
    m = compute_marginals(V, c.n1, c.n2, c.n3, printed);
  }
  return flips;
}

TEST(HopfieldDiscrete, NoFlipSkipEqualsAReferenceThatReadsEveryNeuron) {
  CounterRng rng(41, 2);
  int64_t total_flips = 0;
  for (const Dims& d : {Dims{10, 10, 10}, Dims{9, 11, 13}})
    for (HopfieldEnergy form : kForms)
      for (int variant = 0; variant < 4; ++variant) {
        CostTensor3 t = random_tensor(d.n1, d.n2, d.n3, 900 + variant);
        if (variant >= 2)  // forbidden tuples: ĉ = 1 + margin, c_hi = 2
          for (auto& b : t.cost)
            if (rng.uniform() < 0.3) b = std::numeric_limits<float>::infinity();
        const NormalisedCost c = normalise_cost(t);
        HopfieldWeights w{1.f, 1.f, 1.f, 0.f, 1.4f, std::min({d.n1, d.n2, d.n3})};
        if (variant == 1) w = some_weights(rng, w.N);
        if (variant == 3) w.E = -0.7f;  // rewards cost: the bounds swap ends
        if (form == HopfieldEnergy::kPrinted) w.D = 1.f;
        // Near-valid start: a partial assignment (rows kept with prob. 0.8) plus a few strays.
        std::vector<uint8_t> V0(c.size(), 0);
        const int32_t m = w.N;
        for (int32_t r = 0; r < m; ++r)
          if (rng.uniform() < 0.8) V0[c.size() / m * r % c.size()] = 1;
        for (int extra = 0; extra < 4; ++extra) V0[rng.uniform_int(c.size())] = 1;
        std::vector<uint32_t> cost_order = ascending_cost_order(c.c), random_order(c.size());
        std::iota(random_order.begin(), random_order.end(), 0u);
        const OrderedSweepPlan plan(cost_order, c);
        DiscreteNetwork planned(form, w, c), plain(form, w, c);
        planned.set_state(V0);
        plain.set_state(V0);
        std::vector<uint8_t> ref = V0, ref_random = V0;
        DiscreteNetwork shuffled(form, w, c);
        shuffled.set_state(V0);
        for (int sweep = 0; sweep < 6; ++sweep) {
          const int64_t fr = reference_async_sweep(form, w, c, ref, cost_order);
          ASSERT_EQ(async_sweep_planned(planned, plan), fr) << variant << " sweep " << sweep;
          ASSERT_EQ(async_sweep(plain, cost_order), fr);
          ASSERT_EQ(planned.V, ref) << enum_name(form) << " variant " << variant << " sweep " << sweep;
          ASSERT_EQ(plain.V, ref);
          rng.shuffle(std::span<uint32_t>(random_order));
          const int64_t fq = reference_async_sweep(form, w, c, ref_random, random_order);
          ASSERT_EQ(async_sweep(shuffled, random_order), fq);
          ASSERT_EQ(shuffled.V, ref_random) << enum_name(form) << " variant " << variant;
          total_flips += fr + fq;
        }
        expect_marginals_recomputed(planned);
      }
  EXPECT_GT(total_flips, 100);  // the sweeps did work, not only skips
}

// The planned sweep (order, indices and costs laid out once) makes the same updates as async_sweep
// in the same order: identical states, marginals and flip counts, sweep by sweep, both energies,
// for the cost order and for random orders, on square and rectangular shapes.
TEST(HopfieldDiscrete, PlannedAsyncEqualsAsyncInTheSameOrder) {
  CounterRng rng(31, 2);
  for (const Dims& d : {Dims{5, 5, 5}, Dims{3, 4, 5}, Dims{12, 9, 14}, Dims{20, 20, 20}})
    for (HopfieldEnergy form : kForms) {
      const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 77));
      HopfieldWeights w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
      for (int variant = 0; variant < 2; ++variant) {
        std::vector<uint32_t> order = ascending_cost_order(c.c);
        if (variant == 1) rng.shuffle(std::span<uint32_t>(order));
        const OrderedSweepPlan plan(order, c);
        DiscreteNetwork a(form, w, c), b(form, w, c);
        const std::vector<uint8_t> V0 = random_state(c.size(), 0.2, rng);
        a.set_state(V0);
        b.set_state(V0);
        int64_t flips = 0;
        for (int sweep = 0; sweep < 4; ++sweep) {
          const int64_t fa = async_sweep_planned(a, plan), fb = async_sweep(b, order);
          ASSERT_EQ(fa, fb);
          ASSERT_EQ(a.V, b.V);
          ASSERT_EQ(a.m.R, b.m.R);
          ASSERT_EQ(a.m.S, b.m.S);
          ASSERT_EQ(a.m.T, b.m.T);
          ASSERT_EQ(a.m.Ljk, b.m.Ljk);
          ASSERT_EQ(a.hash, b.hash);
          flips += fa;
        }
        EXPECT_GT(flips, 0);
      }
    }
}

// E·ĉ_max < (A+B+C+D)/2 makes every valid assignment a fixed point of the full-plane network
// (docs/design.md §4.4), under every schedule; above the bound the most expensive one is not.
TEST(HopfieldDiscrete, EveryValidAssignmentIsAFixedPointBelowTheBound) {
  CounterRng rng(11, 2);
  const int32_t n = 5;
  const NormalisedCost c = normalise_cost(random_tensor(n, n, n, 400));
  for (int trial = 0; trial < 20; ++trial) {
    HopfieldWeights w = some_weights(rng, n);
    const bool with_D = trial % 2 == 0;
    if (!with_D) w.D = 0;
    w.E = static_cast<float>(0.99 * fixed_point_E_bound(w));  // ĉ_max = 1
    const std::vector<uint8_t> V = permutation_state(n, rng);
    DiscreteNetwork net(HopfieldEnergy::kFullPlane, w, c);
    net.set_state(V);
    std::vector<uint32_t> order(c.size());
    std::iota(order.begin(), order.end(), 0u);
    EXPECT_EQ(async_sweep(net, order), 0);
    EXPECT_EQ(sync_sweep(net, 1.0, 0).flips, 0);
    EXPECT_EQ(net.V, V);
    if (!with_D) {
      DiagonalNetwork diag(w, c);
      diag.set_state(V);
      std::vector<uint32_t> blocks(diag.num_blocks());
      std::iota(blocks.begin(), blocks.end(), 0u);
      EXPECT_EQ(diag.sweep(blocks), 0);
    }
  }
  // Above the bound: an active neuron with ĉ = 1 switches off.
  HopfieldWeights w{1, 1, 1, 0, 2.0f, n};
  std::vector<uint8_t> V(c.size(), 0);
  const std::size_t worst = std::max_element(c.c.begin(), c.c.end()) - c.c.begin();
  V[worst] = 1;
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, w, c);
  net.set_state(V);
  EXPECT_GT(net.delta_on(worst), 0.0);  // so turning it off lowers the energy
}

// Sync from the empty state with small E switches every neuron on, then every neuron off: the
// classic Jacobi 2-cycle, seen by the Zobrist hash.
TEST(HopfieldDiscrete, SyncTwoCycleFromEmptyState) {
  const int32_t n = 4;
  const NormalisedCost c = normalise_cost(random_tensor(n, n, n, 2));
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, HopfieldWeights{1, 1, 1, 0, 1.4f, n}, c);
  const uint64_t h0 = net.hash;
  EXPECT_EQ(sync_sweep(net).flips, 64);
  EXPECT_NE(net.hash, h0);
  EXPECT_EQ(sync_sweep(net).flips, 64);
  EXPECT_EQ(net.hash, h0);
}

}  // namespace
}  // namespace trackassoc
