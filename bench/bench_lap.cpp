// Benchmarks of the Jonker–Volgenant LAP (kernels/assignment/lap.hpp) at n = 100, 1000, 2000 on uniform and
// geometric (squared-distance) costs, the matrices of bench/lap_matrices.hpp. The peer is scipy's
// linear_sum_assignment on the same matrices: bench/lap_scipy.py (run by scripts/bench.sh or by
// hand: /usr/bin/python3 bench/lap_scipy.py). The counter `objective` lets the two runs be checked
// against each other (same matrix, same optimum). BM_LapPlain is the same solver without JV's
// initialisation phases (LapOptions::initialise = false: the plain shortest augmenting path, the
// algorithm scipy uses), so the gain of the initialisation is measured in the same run; the counter
// `augmented` is the number of rows left to the augmentation phase.
//
// One LAP is inherently sequential (each augmentation depends on the last), so the thread variant
// is a batch of 4 independent LAPs spread over the threads with parallel_for_range: the throughput
// a Monte Carlo study sees.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <map>
#include <utility>

#include "bench/lap_matrices.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc::bench {
namespace {

const std::vector<double>& matrix(bool geometric, int n) {
  static std::map<std::pair<bool, int>, std::vector<double>> cache;
  auto& m = cache[{geometric, n}];
  if (m.empty()) m = geometric ? lap_geometric_matrix(n) : lap_uniform_matrix(n);
  return m;
}

void run_lap(benchmark::State& state, bool geometric, bool initialise) {
  const int n = static_cast<int>(state.range(0));
  const auto& c = matrix(geometric, n);
  LapOptions options;
  options.initialise = initialise;
  double objective = 0.0;
  int32_t augmented = 0;
  for (auto _ : state) {
    const LapResult r = solve_lap(c, n, n, options);
    objective = r.cost;
    augmented = r.augmented_rows;
    benchmark::DoNotOptimize(r.row_to_col.data());
  }
  state.counters["objective"] = objective;
  state.counters["n"] = n;
  state.counters["augmented"] = augmented;
}

void BM_Lap(benchmark::State& state, bool geometric) { run_lap(state, geometric, true); }
void BM_LapPlain(benchmark::State& state, bool geometric) { run_lap(state, geometric, false); }

void BM_LapBatch4(benchmark::State& state, bool geometric) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  const auto& c = matrix(geometric, n);
  std::vector<double> costs(4);
  for (auto _ : state) {
    parallel_for_range(4, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) costs[t] = solve_lap(c, n, n).cost;
    });
    benchmark::DoNotOptimize(costs.data());
  }
  state.counters["laps_per_s"] = benchmark::Counter(4.0 * state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_Lap, uniform, false)->Arg(100)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Lap, geometric, true)->Arg(100)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LapPlain, uniform, false)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LapPlain, geometric, true)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LapBatch4, uniform, false)
    ->Args({1000, 1})
    ->Args({1000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_LapBatch4, geometric, true)
    ->Args({1000, 1})
    ->Args({1000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
