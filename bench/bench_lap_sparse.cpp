// Crossover of the sparse LAP (kernels/assignment/lap_sparse.hpp) against the dense JV
// (kernels/assignment/lap.hpp) on gated association problems: the geometric points of
// bench/lap_matrices.hpp (n = 1000 against 1000 in the unit square), cost |a_i − b_j|² kept only
// inside a gate of radius r, each track free to stay unassigned at half the gate (allow_unassigned,
// unassigned_cost = r²/2, so a pair is worth making only inside the gate). The argument is the
// fraction of pairs inside the gate in per mille (r from π r² = density, edge effects make the
// measured `density` counter a little lower). Dense solves the n×n matrix with +inf outside the
// gate; sparse the candidate lists. Same optimum (`objective` counters).
//   build/bench_lap_sparse --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "bench/lap_matrices.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/assignment/lap_sparse.hpp"

namespace trackassoc::bench {
namespace {

constexpr int kN = 1000;

struct Gated {
  std::vector<double> dense;
  std::vector<int32_t> start{0}, col;
  std::vector<double> cost;
  double unassigned_cost = 0.0, density = 0.0;
};

const Gated& gated(int per_mille) {
  static std::map<int, Gated> cache;
  Gated& g = cache[per_mille];
  if (!g.dense.empty()) return g;
  const double r2 = per_mille / 1000.0 / std::numbers::pi;  // π r² = density
  g.unassigned_cost = r2 / 2.0;
  g.dense = lap_geometric_matrix(kN);
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      double& x = g.dense[static_cast<std::size_t>(i) * kN + j];
      if (x < r2) {
        g.col.push_back(j);
        g.cost.push_back(x);
      } else {
        x = std::numeric_limits<double>::infinity();
      }
    }
    g.start.push_back(static_cast<int32_t>(g.col.size()));
  }
  g.density = static_cast<double>(g.col.size()) / (static_cast<double>(kN) * kN);
  return g;
}

void report(benchmark::State& state, const Gated& g, const LapResult& r) {
  state.counters["objective"] = r.cost;
  state.counters["density"] = g.density;
  state.counters["augmented"] = r.augmented_rows;
}

void BM_GatedDense(benchmark::State& state) {
  const Gated& g = gated(static_cast<int>(state.range(0)));
  const LapOptions o{true, g.unassigned_cost};
  LapResult r;
  for (auto _ : state) {
    r = solve_lap(g.dense, kN, kN, o);
    benchmark::DoNotOptimize(r.row_to_col.data());
  }
  report(state, g, r);
}

void BM_GatedSparse(benchmark::State& state) {
  const Gated& g = gated(static_cast<int>(state.range(0)));
  const LapOptions o{true, g.unassigned_cost};
  const SparseCostView view{kN, kN, g.start, g.col, g.cost};
  LapResult r;
  for (auto _ : state) {
    r = solve_sparse_lap(view, o);
    benchmark::DoNotOptimize(r.row_to_col.data());
  }
  report(state, g, r);
}

void densities(benchmark::internal::Benchmark* b) {
  for (const int per_mille : {2, 5, 10, 20, 50, 100, 200, 500}) b->Arg(per_mille);
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_GatedDense)->Apply(densities);
BENCHMARK(BM_GatedSparse)->Apply(densities);

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
