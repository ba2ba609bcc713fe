// The diagonal schedule (kernels/hopfield/hopfield_diagonal.hpp): the block layout, exact asynchronous
// semantics (a block equals async updates of its neurons and never raises the energy), the
// vector path equal to the scalar segment loop it replaced, neuron for neuron and sweep by sweep,
// and thread-count independence of the solver with this schedule.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <numeric>

#include "kernels/core/error.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "kernels/hopfield/hopfield_diagonal.hpp"
#include "kernels/hopfield/hopfield_discrete.hpp"
#include "tests/support/hopfield_instances.hpp"
#include "tests/support/hopfield_test_support.hpp"

namespace trackassoc {
namespace {

using namespace hopfield_test;

// Shapes below and above the vector width (16), square and rectangular, n1 a multiple of 16 or not.
const Dims kDiagonalDims[] = {{4, 4, 4},    {5, 5, 5},    {3, 4, 5},    {3, 5, 4},   {16, 16, 16},
                              {17, 19, 23}, {20, 33, 21}, {16, 16, 40}, {33, 33, 33}};

TEST(HopfieldDiagonal, LayoutHoldsEachBlockContiguously) {
  for (const Dims& d : {Dims{3, 4, 5}, Dims{17, 19, 23}}) {
    const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 7));
    const DiagonalCost layout(c);
    ASSERT_EQ(layout.c.size(), c.size());
    for (int32_t a = 0; a < d.n2; ++a)
      for (int32_t b = 0; b < d.n3; ++b)
        for (int32_t i = 0; i < d.n1; ++i) {
          const std::size_t standard =
              (static_cast<std::size_t>(i) * d.n2 + (i + a) % d.n2) * d.n3 + (i + b) % d.n3;
          ASSERT_EQ(layout.standard_index(a, b, i), standard);
          ASSERT_EQ(layout.c[(static_cast<std::size_t>(a) * d.n3 + b) * d.n1 + i], c.c[standard]);
        }
    // The blocks partition the neurons, and the state survives the round trip.
    DiagonalNetwork net(HopfieldWeights{1, 1, 1, 0, 1, d.n1}, c);
    CounterRng rng(3);
    const std::vector<uint8_t> V = random_state(c.size(), 0.3, rng);
    net.set_state(V);
    std::vector<uint8_t> back(V.size(), 7);
    net.get_state(back);
    EXPECT_EQ(back, V);
  }
}

// A diagonal block update is exactly an asynchronous pass over its neurons (any order: here the
// reverse one) and never raises the full-plane energy (D = 0). Both paths: n1 < 16 runs the scalar
// loop, n1 ≥ 16 the vector one.
TEST(HopfieldDiagonal, BlocksNeverRaiseEnergyAndMatchAsync) {
  CounterRng rng(12, 2);
  for (const Dims& d : kDiagonalDims)
    for (int trial = 0; trial < 2; ++trial) {
      const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 500 + trial));
      HopfieldWeights w = some_weights(rng, d.n1);
      w.D = 0;
      DiagonalNetwork diag(w, c);
      DiscreteNetwork net(HopfieldEnergy::kFullPlane, w, c);
      const std::vector<uint8_t> V0 = random_state(c.size(), 1.5 / d.n2 / d.n3, rng);
      diag.set_state(V0);
      net.set_state(V0);
      std::vector<uint32_t> blocks(diag.num_blocks());
      std::iota(blocks.begin(), blocks.end(), 0u);
      std::vector<uint8_t> V(c.size());
      double E = net.energy();
      int64_t flips = 0, async_flips = 0;
      for (int sweep = 0; sweep < 3; ++sweep) {
        rng.shuffle(std::span<uint32_t>(blocks));
        for (uint32_t b : blocks) {
          flips += diag.sweep(std::span<const uint32_t>(&b, 1));
          std::vector<uint32_t> members;
          for (int32_t i = d.n1 - 1; i >= 0; --i)
            members.push_back(static_cast<uint32_t>(diag.standard_index(b / d.n3, b % d.n3, i)));
          async_flips += async_sweep(net, members);
          if (d.n1 * d.n2 * d.n3 > 4000 && b % 7 != 0) continue;  // check the big shapes on a sample
          diag.get_state(V);
          ASSERT_EQ(V, net.V) << d.n1 << "x" << d.n2 << "x" << d.n3;
          const double E1 = hopfield_energy(HopfieldEnergy::kFullPlane, w, c, V);
          ASSERT_LE(E1, E + 1e-6);
          E = E1;
        }
      }
      diag.get_state(V);
      EXPECT_EQ(V, net.V);
      EXPECT_EQ(flips, async_flips);
      EXPECT_GT(flips, 0);
    }
}

// The vector path reproduces the scalar segment loop (the implementation it replaced) exactly:
// the same state and flip count after every sweep, with E annealed between sweeps as the solver
// does, for random weights, states and block orders.
TEST(HopfieldDiagonal, VectorPathEqualsScalarReferenceSweepBySweep) {
  CounterRng rng(21, 4);
  int64_t total_flips = 0;
  for (const Dims& d : kDiagonalDims)
    for (int trial = 0; trial < 3; ++trial) {
      const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 900 + trial));
      HopfieldWeights w = trial == 0 ? HopfieldWeights{1, 1, 1, 0, 1.4985f, d.n1} : some_weights(rng, d.n1);
      w.D = 0;
      auto layout = std::make_shared<const DiagonalCost>(c);
      DiagonalNetwork fast(w, layout), reference(w, layout);
      const std::vector<uint8_t> V0 = random_state(c.size(), (1 + trial) * 1.0 / d.n2 / d.n3, rng);
      fast.set_state(V0);
      reference.set_state(V0);
      std::vector<uint32_t> blocks(fast.num_blocks());
      std::iota(blocks.begin(), blocks.end(), 0u);
      std::vector<uint8_t> Vf(c.size()), Vr(c.size());
      for (int sweep = 0; sweep < 6; ++sweep) {
        const float E = w.E * (sweep < 3 ? 3.f - sweep : 1.f);
        fast.set_E(E);
        reference.set_E(E);
        rng.shuffle(std::span<uint32_t>(blocks));
        const int64_t ff = fast.sweep(blocks), fr = reference.sweep_reference(blocks);
        ASSERT_EQ(ff, fr) << d.n1 << "x" << d.n2 << "x" << d.n3 << " sweep " << sweep;
        fast.get_state(Vf);
        reference.get_state(Vr);
        ASSERT_EQ(Vf, Vr) << d.n1 << "x" << d.n2 << "x" << d.n3 << " sweep " << sweep;
        total_flips += ff;
      }
      // and the marginals each path keeps agree with the state (a fresh network from it agrees)
      DiagonalNetwork fresh(w, layout);
      fresh.set_state(Vf);
      fresh.set_E(w.E);
      fast.set_E(w.E);
      rng.shuffle(std::span<uint32_t>(blocks));
      EXPECT_EQ(fast.sweep(blocks), fresh.sweep(blocks));
    }
  EXPECT_GT(total_flips, 1000);
}

TEST(HopfieldDiagonal, ValidPermutationIsAFixedPointOnTheVectorPath) {
  CounterRng rng(5, 5);
  const int32_t n = 24;
  const NormalisedCost c = normalise_cost(random_tensor(n, n, n, 44));
  const HopfieldWeights w{1.2f, 0.9f, 1.1f, 0.f, 0.99f * 1.6f, n};  // E·ĉ_max < (A+B+C)/2 = 1.6
  DiagonalNetwork diag(w, c);
  const std::vector<uint8_t> V = permutation_state(n, rng);
  diag.set_state(V);
  std::vector<uint32_t> blocks(diag.num_blocks());
  std::iota(blocks.begin(), blocks.end(), 0u);
  rng.shuffle(std::span<uint32_t>(blocks));
  EXPECT_EQ(diag.sweep(blocks), 0);
  std::vector<uint8_t> back(V.size());
  diag.get_state(back);
  EXPECT_EQ(back, V);
}

TEST(HopfieldDiagonal, RejectsDTermAndBadShape) {
  const NormalisedCost c = normalise_cost(random_tensor(4, 4, 4, 1));
  EXPECT_THROW(DiagonalNetwork(HopfieldWeights{1, 1, 1, 1, 1, 4}, c), InputError);
  const NormalisedCost c2 = normalise_cost(random_tensor(5, 4, 4, 1));
  EXPECT_THROW(DiagonalNetwork(HopfieldWeights{1, 1, 1, 0, 1, 4}, c2), InputError);
  EXPECT_THROW(DiagonalCost{c2}, InputError);
}

// The solver with the diagonal schedule on the vector path (n = 20): identical restarts for 1 and
// 2 threads, and every restart's trace never rises (each sweep is a sequence of async updates;
// the trace is taken with the final E after annealing ends, so compare from there).
TEST(HopfieldDiagonal, SolverIdenticalForOneAndTwoThreadsAndDescends) {
  GeometricInstanceOptions go;
  go.n = 20;
  const GeometricInstance g = make_geometric_instance(go, 31);
  for (HopfieldInit init : {HopfieldInit::kRandom, HopfieldInit::kMeanField}) {
    HopfieldOptions o;
    o.schedule = HopfieldSchedule::kDiagonal;
    o.init = init;
    o.init_density = 3.0;
    o.restarts = 5;
    o.trace = true;
    o.mean_field_steps = 80;
    HopfieldResult r1, r2;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
      r1 = solve_hopfield(g.cost, o, 17);
    }
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
      r2 = solve_hopfield(g.cost, o, 17);
    }
    EXPECT_EQ(r1.solution.tuples, r2.solution.tuples);
    ASSERT_EQ(r1.restarts.size(), r2.restarts.size());
    for (std::size_t i = 0; i < r1.restarts.size(); ++i) {
      EXPECT_EQ(r1.restarts[i].energy_trace, r2.restarts[i].energy_trace);
      EXPECT_EQ(r1.restarts[i].sweeps, r2.restarts[i].sweeps);
      const auto& tr = r1.restarts[i].energy_trace;
      for (std::size_t s = 1; s < tr.size(); ++s) EXPECT_LE(tr[s], tr[s - 1] + 1e-4f) << "restart " << i;
    }
    EXPECT_TRUE(r1.solution.summary.feasible);
  }
}

}  // namespace
}  // namespace trackassoc
