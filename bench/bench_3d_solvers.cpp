// Benchmarks of the 3-D assignment solvers, 1 and 2 threads (Arg 1 = thread count):
//  - BM_LagrangianToOnePercent/n/threads: the Lagrangian relaxation (lr and lr+ls) run until a
//    relative gap ≤ 1 % on tracking cost tensors (below), n = 50, 100, 200. Counters: iterations,
//    final gap, whether the 1 % target was reached.
//  - BM_ExactBalasSaltzman/n/threads: branch and bound on the five Balas–Saltzman instances of size
//    n (14 … 26) per iteration; counters: nodes, all_optimal.
//  - BM_ExactDecompLib/n/r: branch and bound on DecompLib ap3.n.r (n = 5 … 50, r = 1 … 10), one
//    thread (the peer's setting); counters: nodes, root_bound (after the clique cuts), fixed_tuples
//    (by reduced cost, first search pass), optimal (proven and equal to ap3.opt).
//  - BM_LagrangianDecompLib/n/r: lr with its defaults (300 iterations or a 0.1 % gap) on ap3.n.r,
//    n = 40, 50, one thread; counters: lower_bound (the Lagrangian dual bound), objective. Its peer
//    is the LP relaxation CBC solves first (CLP; bench/cbc_3d.py reports its bound and time from
//    the same CBC runs): the Lagrangian dual of the axial 3-AP bounds at most the LP bound.
// The MILP peer (CBC) runs on the same files: bench/cbc_3d.py (--set decomplib; --ours merges this
// binary's JSON output into one table, docs/performance.md, "exact branch and bound").
//
// Tracking cost tensor (tracking_cost_tensor): n targets at uniform positions in a 1000 m square;
// sensor s ∈ {1, 2, 3} reports every target with Gaussian position noise σ_s = 10, 15, 20 m
// (covariance P_s = σ_s² I) in its own random track order; λ_st(a, b) = dᵀ (P_s + P_t)⁻¹ d, the
// squared Mahalanobis distance of the two estimates (seed 000 Eq. 1 at one time step), and
// b_ijk = λ_12(i, j) + λ_23(j, k) (seed 000 Eq. 3, the chain form). CounterRng(seed 2026, n, s).
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <map>
#include <string>

#include "io/instance_text.hpp"
#include "kernels/assignment/branch_and_bound.hpp"
#include "kernels/assignment/lagrangian_relaxation.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc::bench {
namespace {

CostTensor3 tracking_cost_tensor(int n) {
  CounterRng truth_rng(2026, static_cast<uint64_t>(n), 0);
  std::vector<double> tx(n), ty(n);
  for (int t = 0; t < n; ++t) {
    tx[t] = truth_rng.uniform(0.0, 1000.0);
    ty[t] = truth_rng.uniform(0.0, 1000.0);
  }
  const double sigma[3] = {10.0, 15.0, 20.0};
  std::vector<double> x[3], y[3];
  for (int s = 0; s < 3; ++s) {
    CounterRng rng(2026, static_cast<uint64_t>(n), static_cast<uint64_t>(s + 1));
    std::vector<int32_t> order(n);
    for (int t = 0; t < n; ++t) order[t] = t;
    rng.shuffle(std::span<int32_t>(order));  // each sensor numbers its tracks its own way
    x[s].resize(n);
    y[s].resize(n);
    for (int r = 0; r < n; ++r) {
      x[s][r] = tx[order[r]] + rng.normal(0.0, sigma[s]);
      y[s][r] = ty[order[r]] + rng.normal(0.0, sigma[s]);
    }
  }
  auto lambda = [&](int s, int a, int t, int b) {
    const double dx = x[s][a] - x[t][b], dy = y[s][a] - y[t][b];
    return (dx * dx + dy * dy) / (sigma[s] * sigma[s] + sigma[t] * sigma[t]);
  };
  CostTensor3 c(n, n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double l12 = lambda(0, i, 1, j);
      for (int k = 0; k < n; ++k) c.at(i, j, k) = static_cast<float>(l12 + lambda(1, j, 2, k));
    }
  return c;
}

const CostTensor3& tracking(int n) {
  static std::map<int, CostTensor3> cache;
  auto& t = cache[n];
  if (t.n1 == 0) t = tracking_cost_tensor(n);
  return t;
}

void BM_LagrangianToOnePercent(benchmark::State& state, bool local_search) {
  const int n = static_cast<int>(state.range(0));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  const CostTensor3& b = tracking(n);
  LagrangianOptions o;
  o.relative_gap_tolerance = 0.01;
  o.max_iterations = 1000;
  o.local_search = local_search;
  Solution3 s;
  for (auto _ : state) {
    s = solve_lagrangian3(b, o);
    benchmark::DoNotOptimize(s.tuples.data());
  }
  state.counters["iterations"] = static_cast<double>(s.summary.iterations);
  state.counters["gap_pct"] = 100.0 * s.summary.gap;
  state.counters["reached_1pct"] = s.summary.gap <= 0.01 ? 1 : 0;
  state.counters["objective"] = s.summary.objective;
}

void BM_ExactBalasSaltzman(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  const std::string dir = std::string(TRACKASSOC_SHARED_DIR) + "/benchmarks/3dap/balas-saltzman/";
  const auto optima = read_known_optima(dir + "bs.opt");
  std::vector<CostTensor3> instances;
  std::vector<double> known;
  for (int r = 1; r <= 5; ++r) {
    const std::string name = "bs." + std::to_string(n) + "." + std::to_string(r);
    instances.push_back(read_3dap_instance(dir + name + ".txt"));
    known.push_back(optima.at(name));
  }
  int64_t nodes = 0;
  bool all_optimal = true;
  for (auto _ : state) {
    nodes = 0;
    all_optimal = true;
    for (std::size_t q = 0; q < instances.size(); ++q) {
      const Solution3 s = solve_branch_and_bound3(instances[q]);
      nodes += s.summary.iterations;
      all_optimal &= s.summary.termination == Termination::kOptimal && s.summary.objective == known[q];
    }
  }
  state.counters["nodes_per_instance"] = static_cast<double>(nodes) / 5.0;
  state.counters["all_optimal"] = all_optimal ? 1 : 0;
  state.counters["s_per_instance"] =
      benchmark::Counter(5.0 * state.iterations(), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_ExactDecompLib(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), r = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  const std::string dir = std::string(TRACKASSOC_SHARED_DIR) + "/benchmarks/3dap/decomplib/";
  const std::string name = "ap3." + std::to_string(n) + "." + std::to_string(r);
  const CostTensor3 instance = read_3dap_instance(dir + name + ".txt");
  const double known = read_known_optima(dir + "ap3.opt").at(name);
  Solution3 s;
  BranchAndBoundStats stats;
  for (auto _ : state) {
    s = solve_branch_and_bound3(instance, {}, &stats);
    benchmark::DoNotOptimize(s.tuples.data());
  }
  state.counters["nodes"] = static_cast<double>(s.summary.iterations);
  state.counters["root_bound"] = stats.root_bound;
  state.counters["fixed_tuples"] = static_cast<double>(stats.fixed_tuples);
  state.counters["objective"] = s.summary.objective;
  state.counters["optimal"] =
      s.summary.termination == Termination::kOptimal && s.summary.objective == known ? 1 : 0;
}

void BM_LagrangianDecompLib(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), r = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
  const std::string dir = std::string(TRACKASSOC_SHARED_DIR) + "/benchmarks/3dap/decomplib/";
  const CostTensor3 instance =
      read_3dap_instance(dir + "ap3." + std::to_string(n) + "." + std::to_string(r) + ".txt");
  Solution3 s;
  for (auto _ : state) {
    s = solve_lagrangian3(instance, LagrangianOptions{});
    benchmark::DoNotOptimize(s.tuples.data());
  }
  state.counters["lower_bound"] = s.summary.lower_bound;
  state.counters["objective"] = s.summary.objective;
  state.counters["iterations"] = static_cast<double>(s.summary.iterations);
}

void decomplib_args(benchmark::internal::Benchmark* b) {
  for (int n : {5, 10, 20, 30, 40, 50})
    for (int r = 1; r <= 10; ++r) b->Args({n, r});
}

void decomplib_lr_args(benchmark::internal::Benchmark* b) {
  for (int n : {40, 50})
    for (int r = 1; r <= 10; ++r) b->Args({n, r});
}

void lr_args(benchmark::internal::Benchmark* b) {
  for (int n : {50, 100, 200})
    for (int t : {1, 2}) b->Args({n, t});
}
void bs_args(benchmark::internal::Benchmark* b) {
  for (int n = 14; n <= 26; n += 2)
    for (int t : {1, 2}) b->Args({n, t});
}

BENCHMARK_CAPTURE(BM_LagrangianToOnePercent, lr, false)
    ->Apply(lr_args)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_LagrangianToOnePercent, lr_ls, true)
    ->Apply(lr_args)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ExactBalasSaltzman)->Apply(bs_args)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExactDecompLib)->Apply(decomplib_args)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LagrangianDecompLib)->Apply(decomplib_lr_args)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
