// Benchmarks of the association kernels (docs/design.md §6):
//   * the dense cost tensor (chain and all-pairs) at n = 50, 100, 200 per sensor, 1 and 2 threads,
//     in bytes written per second, beside a STREAM-style write of the same number of floats with
//     the same TBB split (the memory floor) and a naive serial triple loop (the peer);
//   * the sequential statistic for n = 100 tracks per sensor and K = 20 common times.
// Args: {n, threads}. Ratios are taken from one run of this binary.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <vector>

#include "kernels/core/parallel.hpp"
#include "kernels/core/random.hpp"
#include "kernels/statistics/association_statistic.hpp"
#include "kernels/statistics/cost_tensor.hpp"

namespace trackassoc {
namespace {

PairStatistic random_statistic(int32_t na, int32_t nb, uint64_t stream) {
  CounterRng rng(1, stream);
  PairStatistic s;
  s.n_a = na;
  s.n_b = nb;
  const std::size_t m = static_cast<std::size_t>(na) * nb;
  s.lambda.resize(m);
  s.dof.assign(m, 80);
  s.in_gate.resize(m);
  for (std::size_t p = 0; p < m; ++p) {
    s.lambda[p] = rng.uniform(0, 60);
    s.in_gate[p] = rng.uniform() < 0.5;
  }
  return s;
}

void set_tensor_counters(benchmark::State& state, std::size_t floats) {
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(floats * sizeof(float)));
  state.counters["floats"] = static_cast<double>(floats);
  state.counters["threads"] = static_cast<double>(state.range(1));
}

void BM_CostTensor(benchmark::State& state, CostForm form) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(1)));
  const PairStatistic s12 = random_statistic(n, n, 1), s23 = random_statistic(n, n, 2),
                      s13 = random_statistic(n, n, 3);
  CostTensorOptions opt;
  opt.form = form;
  CostTensor3 out;
  build_cost_tensor_into(s12, s23, &s13, opt, out);  // allocate and fault in the pages once
  for (auto _ : state) {
    build_cost_tensor_into(s12, s23, &s13, opt, out);
    benchmark::DoNotOptimize(out.cost.data());
    benchmark::ClobberMemory();
  }
  set_tensor_counters(state, out.size());
}
void BM_CostTensorChain(benchmark::State& state) { BM_CostTensor(state, CostForm::kChain); }
void BM_CostTensorAllPairs(benchmark::State& state) { BM_CostTensor(state, CostForm::kAllPairs); }

// The allocating entry point: includes the zero-fill and page faults of a fresh tensor.
void BM_CostTensorChainFresh(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(1)));
  const PairStatistic s12 = random_statistic(n, n, 1), s23 = random_statistic(n, n, 2);
  std::size_t floats = 0;
  for (auto _ : state) {
    CostTensor3 out = build_cost_tensor(s12, s23, nullptr, CostTensorOptions{});
    benchmark::DoNotOptimize(out.cost.data());
    floats = out.size();
  }
  set_tensor_counters(state, floats);
}

// STREAM-style floor: write the same number of floats, same TBB split over n slices of n² floats.
void BM_StreamWrite(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(1)));
  const std::size_t slice = n * n;
  std::vector<float> a(n * slice, 0.f);
  float value = 1.f;
  const std::size_t grain = std::max<std::size_t>(1, (std::size_t{1} << 16) / slice);
  for (auto _ : state) {
    float* p = a.data();
    const float v = value;
    parallel_for_range(n, grain, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t q = lo * slice; q < hi * slice; ++q) p[q] = v;
    });
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
    value += 1.f;
  }
  set_tensor_counters(state, a.size());
}

// The peer: a straightforward serial triple loop with the gate test per element.
void BM_CostTensorChainNaive(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const PairStatistic s12 = random_statistic(n, n, 1), s23 = random_statistic(n, n, 2);
  CostTensor3 out(n, n, n);
  const float gated = 600.f;
  for (auto _ : state) {
    for (int32_t i = 0; i < n; ++i)
      for (int32_t j = 0; j < n; ++j)
        for (int32_t k = 0; k < n; ++k) {
          const std::size_t ij = static_cast<std::size_t>(i) * n + j,
                            jk = static_cast<std::size_t>(j) * n + k;
          out.at(i, j, k) = static_cast<float>((s12.in_gate[ij] ? s12.lambda[ij] : gated) +
                                               (s23.in_gate[jk] ? s23.lambda[jk] : gated));
        }
    benchmark::DoNotOptimize(out.cost.data());
    benchmark::ClobberMemory();
  }
  set_tensor_counters(state, out.size());
}

// Sequential statistic: n tracks per sensor, K common times, D = 4, every track valid always.
AlignedTracks random_aligned(int32_t n, int32_t K, uint64_t stream) {
  CounterRng rng(3, stream);
  AlignedTracks x;
  x.sensor = static_cast<int32_t>(stream);
  x.dim = 4;
  x.n_times = K;
  for (int32_t i = 0; i < n; ++i) {
    x.track.push_back(i);
    x.truth.push_back(i);
  }
  x.allocate_full();
  const std::size_t cells = static_cast<std::size_t>(x.cells());
  x.valid.assign(cells, 1);
  for (std::size_t c = 0; c < cells; ++c) {
    for (int d = 0; d < 4; ++d) x.state[c * 4 + d] = rng.uniform(-1e4, 1e4);
    const double p = rng.uniform(100, 400), v = rng.uniform(1, 10), pv = rng.uniform(0, 5);
    // packed upper triangle of [[p,0,pv,0],[0,p,0,pv],[pv,0,v,0],[0,pv,0,v]]
    const double packed[10] = {p, 0, pv, 0, p, 0, pv, v, 0, v};
    for (int q = 0; q < 10; ++q) x.cov[c * 10 + q] = packed[q];
  }
  return x;
}

void BM_Statistic(benchmark::State& state, bool correlated) {
  const int32_t n = static_cast<int32_t>(state.range(0)), K = 20;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(1)));
  const AlignedTracks a = random_aligned(n, K, 1), b = random_aligned(n, K, 2);
  StatisticOptions opt;
  opt.correlated = correlated;
  opt.cross_correlation = correlated ? 0.3 : 0.0;
  for (auto _ : state) {
    PairStatistic s = independent_sequential_statistic(a, b, opt);
    benchmark::DoNotOptimize(s.lambda.data());
  }
  state.counters["pair_times_per_s"] =
      benchmark::Counter(static_cast<double>(n) * n * K, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = static_cast<double>(state.range(1));
}
void BM_StatisticIndependent(benchmark::State& state) { BM_Statistic(state, false); }
void BM_StatisticCorrelated(benchmark::State& state) { BM_Statistic(state, true); }

void tensor_args(benchmark::internal::Benchmark* b) {
  for (int n : {50, 100, 200})
    for (int t : {1, 2}) b->Args({n, t});
  b->ArgNames({"n", "threads"})->Unit(benchmark::kMicrosecond)->UseRealTime();
}

BENCHMARK(BM_CostTensorChain)->Apply(tensor_args);
BENCHMARK(BM_CostTensorAllPairs)->Apply(tensor_args);
BENCHMARK(BM_StreamWrite)->Apply(tensor_args);
BENCHMARK(BM_CostTensorChainFresh)
    ->Args({200, 1})
    ->Args({200, 2})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_CostTensorChainNaive)
    ->Args({200, 1})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_StatisticIndependent)
    ->Args({100, 1})
    ->Args({100, 2})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_StatisticCorrelated)
    ->Args({100, 1})
    ->Args({100, 2})
    ->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace trackassoc

BENCHMARK_MAIN();
