// The continuous Hopfield network (kernels/hopfield/hopfield_continuous.hpp) against a from-scratch
// double-precision reference of the Hopfield–Tank Euler step, and the Lyapunov property of its
// asynchronous updates.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/hopfield/hopfield_continuous.hpp"
#include "tests/support/hopfield_test_support.hpp"

namespace trackassoc {
namespace {

using namespace hopfield_test;

// Plane sums of V in double, from scratch.
struct PlaneSums {
  std::vector<double> R, S, T;
  double M = 0;
  explicit PlaneSums(const ContinuousNetwork& net) {
    const NormalisedCost& c = *net.c;
    R.assign(c.n1, 0.0), S.assign(c.n2, 0.0), T.assign(c.n3, 0.0);
    for (std::size_t b = 0; b < c.size(); ++b) {
      const double v = net.V[b];
      R[b / (static_cast<std::size_t>(c.n2) * c.n3)] += v;
      S[b / c.n3 % c.n2] += v;
      T[b % c.n3] += v;
      M += v;
    }
  }
};

// h_a = −∂E/∂V_a + λ(A+B+C+D)(V_a − ½) (the header's form), from plane sums of the current V.
double reference_h(const ContinuousNetwork& net, const PlaneSums& q, const ContinuousParams& p,
                   std::size_t a) {
  const NormalisedCost& c = *net.c;
  const std::size_t n2 = c.n2, n3 = c.n3;
  const std::size_t i = a / (n2 * n3), j = a / n3 % n2, k = a % n3;
  const HopfieldWeights& w = p.w;
  return -(w.A * (q.R[i] - 1) + w.B * (q.S[j] - 1) + w.C * (q.T[k] - 1) + w.D * (q.M - w.N) + w.E * c.c[a]) +
         p.self_excitation * (w.A + w.B + w.C + w.D) * (net.V[a] - 0.5);
}
double reference_h(const ContinuousNetwork& net, const ContinuousParams& p, std::size_t a) {
  return reference_h(net, PlaneSums(net), p, a);
}

double reference_V(double u, double u0) { return 0.5 * (1.0 + std::tanh(u / u0)); }

ContinuousParams params(CounterRng& rng, int32_t N) {
  ContinuousParams p;
  p.w = some_weights(rng, N);
  p.dt = 0.05f;
  p.tau = 2.f;
  p.u0 = 0.3f;
  p.self_excitation = 0.1f;
  return p;
}

// One sync step: every u from the previous V (Jacobi), u ← (1 − dt/τ)u + dt·h, V = ½(1+tanh(u/u₀)).
// Small slices take the flat loop, slices above 16384 neurons (3×130×130) the row-by-row loop.
TEST(HopfieldContinuous, SyncStepEqualsTheEulerStepFromScratch) {
  CounterRng rng(51, 2);
  for (const Dims& d : {Dims{3, 4, 5}, Dims{5, 5, 5}, Dims{6, 3, 4}, Dims{3, 130, 130}}) {
    const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 500));
    const ContinuousParams p = params(rng, std::min({d.n1, d.n2, d.n3}));
    ContinuousNetwork net(c);
    net.initialise(-0.2f, 0.3f, p.u0, rng);
    for (int step = 0; step < 3; ++step) {
      const ContinuousNetwork before = net;
      const PlaneSums sums(before);
      std::vector<double> u_ref(c.size()), V_ref(c.size());
      double dmax_ref = 0;
      for (std::size_t a = 0; a < c.size(); ++a) {
        u_ref[a] = (1.0 - p.dt / p.tau) * before.u[a] + p.dt * reference_h(before, sums, p, a);
        V_ref[a] = reference_V(u_ref[a], p.u0);
        dmax_ref = std::max(dmax_ref, std::abs(V_ref[a] - before.V[a]));
      }
      const float dmax = continuous_sync_step(net, p);
      for (std::size_t a = 0; a < c.size(); ++a) {
        ASSERT_NEAR(net.u[a], u_ref[a], 1e-5 * (1.0 + std::abs(u_ref[a])))
            << "step " << step << " neuron " << a;
        ASSERT_NEAR(net.V[a], V_ref[a], 1e-5);
      }
      EXPECT_NEAR(dmax, dmax_ref, 1e-5);
      // The plane sums it carries equal the sums of its V.
      const double M = std::accumulate(net.V.begin(), net.V.end(), 0.0);
      EXPECT_NEAR(net.M, M, 1e-4 * (1.0 + M));
      const PlaneSums after(net);
      for (int32_t j = 0; j < d.n2; ++j) ASSERT_NEAR(net.S[j], after.S[j], 1e-4 * (1.0 + after.S[j]));
      for (int32_t k = 0; k < d.n3; ++k) ASSERT_NEAR(net.T[k], after.T[k], 1e-4 * (1.0 + after.T[k]));
    }
  }
}

// The async step in a given order: each neuron sees the V of those updated before it.
TEST(HopfieldContinuous, AsyncStepEqualsSequentialEulerUpdates) {
  CounterRng rng(52, 2);
  for (const Dims& d : {Dims{3, 4, 5}, Dims{4, 4, 4}}) {
    const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 501));
    const ContinuousParams p = params(rng, std::min({d.n1, d.n2, d.n3}));
    ContinuousNetwork net(c);
    net.initialise(-0.1f, 0.3f, p.u0, rng);
    ContinuousNetwork ref = net;
    std::vector<uint32_t> order(c.size());
    std::iota(order.begin(), order.end(), 0u);
    for (int step = 0; step < 3; ++step) {
      rng.shuffle(std::span<uint32_t>(order));
      for (uint32_t a : order) {
        const double u = (1.0 - p.dt / p.tau) * ref.u[a] + p.dt * reference_h(ref, p, a);
        ref.u[a] = static_cast<float>(u);
        ref.V[a] = static_cast<float>(reference_V(u, p.u0));
      }
      continuous_async_step(net, p, order);
      for (std::size_t a = 0; a < c.size(); ++a) {
        ASSERT_NEAR(net.u[a], ref.u[a], 1e-5) << "step " << step << " neuron " << a;
        ASSERT_NEAR(net.V[a], ref.V[a], 1e-5);
      }
    }
  }
}

// Lyapunov property of the asynchronous updates (λ = 0): updating one neuron moves V_a in the
// direction of h = −∂E/∂V_a, and E is quadratic in V_a with curvature A+B+C+D, so
//   ΔE = −h·ΔV + ½(A+B+C+D)·ΔV² ≤ 0   whenever |ΔV| ≤ 2|h|/(A+B+C+D).
// With τ = 0, |ΔV| ≤ dt·|h|/(2u₀) (the slope of V(u) is at most 1/(2u₀)), so dt ≤ 4u₀/(A+B+C+D)
// suffices. Checked neuron by neuron on random instances and weights.
TEST(HopfieldContinuous, AsyncUpdateNeverRaisesTheEnergyForSmallSteps) {
  CounterRng rng(53, 2);
  int64_t moved = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const Dims d = trial % 2 ? Dims{4, 5, 3} : Dims{5, 5, 5};
    const NormalisedCost c = normalise_cost(random_tensor(d.n1, d.n2, d.n3, 600 + trial));
    ContinuousParams p;
    p.w = some_weights(rng, std::min({d.n1, d.n2, d.n3}));
    p.tau = 0.f;
    p.u0 = static_cast<float>(rng.uniform(0.05, 0.5));
    p.dt = 0.9f * 4.f * p.u0 / (p.w.A + p.w.B + p.w.C + p.w.D);
    ContinuousNetwork net(c);
    net.initialise(0.f, 0.5f, p.u0, rng);
    std::vector<uint32_t> order(c.size());
    std::iota(order.begin(), order.end(), 0u);
    for (int step = 0; step < 4; ++step) {
      rng.shuffle(std::span<uint32_t>(order));
      for (uint32_t a : order) {
        const double E0 = net.energy(p.w);
        const float V0 = net.V[a];
        continuous_async_step(net, p, std::span<const uint32_t>(&a, 1));
        const double E1 = net.energy(p.w);
        ASSERT_LE(E1, E0 + 1e-9 * (1.0 + std::abs(E0))) << "trial " << trial << " neuron " << a;
        moved += net.V[a] != V0;
      }
    }
  }
  EXPECT_GT(moved, 1000);
}

// The sync step is parallel over i-slices and reduces its sums in a fixed order.
TEST(HopfieldContinuous, SyncStepIsIdenticalForOneAndTwoThreads) {
  CounterRng rng(54, 2);
  const NormalisedCost c = normalise_cost(random_tensor(16, 12, 14, 502));
  const ContinuousParams p = params(rng, 12);
  ContinuousNetwork start(c);
  start.initialise(-0.2f, 0.3f, p.u0, rng);
  std::vector<ContinuousNetwork> out;
  for (int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    ContinuousNetwork net = start;
    for (int step = 0; step < 5; ++step) continuous_sync_step(net, p);
    out.push_back(net);
  }
  EXPECT_EQ(out[0].u, out[1].u);
  EXPECT_EQ(out[0].V, out[1].V);
  EXPECT_EQ(out[0].R, out[1].R);
  EXPECT_EQ(out[0].M, out[1].M);
}

}  // namespace
}  // namespace trackassoc
