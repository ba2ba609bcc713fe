// The GNN local tracker (kernels/filters/gnn_tracker.hpp) on many targets per scan: the scan's
// gated track × measurement LAP through the dense JV (lap.max_density = 0) against the sparse
// dispatch (the default, kernels/assignment/lap_sparse.hpp solve_gated_lap), on the same scans.
//
// Scene: N point targets on a square grid 100 m apart, each moving at 5 m/s in a random direction,
// one plot per target per 1 s scan (σ 2 m, no clutter, p_D = 1), 12 scans; the gate (χ²₂(0.999),
// ~10 m here) holds about one measurement per track, so the density of the LAP is ~1/N. Reported
// per run of the 12 scans; `assigned` counts the measurements assigned to existing tracks, equal for
// both solvers.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/filters/gnn_tracker.hpp"

namespace trackassoc {
namespace {

struct Scene {
  std::vector<std::vector<double>> x, y;  // per scan
};

Scene make_scene(int32_t n, int32_t scans) {
  CounterRng rng(20261202, static_cast<uint64_t>(n));
  const int32_t side = static_cast<int32_t>(std::ceil(std::sqrt(static_cast<double>(n))));
  std::vector<double> px(n), py(n), vx(n), vy(n);
  for (int32_t i = 0; i < n; ++i) {
    px[i] = 100.0 * (i % side);
    py[i] = 100.0 * (i / side);
    const double heading = rng.uniform(0.0, 2.0 * M_PI);
    vx[i] = 5.0 * std::cos(heading);
    vy[i] = 5.0 * std::sin(heading);
  }
  Scene s;
  s.x.resize(scans);
  s.y.resize(scans);
  for (int32_t k = 0; k < scans; ++k)
    for (int32_t i = 0; i < n; ++i) {
      s.x[k].push_back(px[i] + vx[i] * k + rng.normal(0.0, 2.0));
      s.y[k].push_back(py[i] + vy[i] * k + rng.normal(0.0, 2.0));
    }
  return s;
}

// Arguments: targets, sparse dispatch (0: always the dense JV).
void BM_GnnTracker(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const Scene scene = make_scene(n, 12);
  GnnTrackerOptions o;
  o.measurement_sigma = 2.0;
  o.cluster_distance = 1.0;  // one plot per target: no merging of neighbours
  if (state.range(1) == 0) o.lap.max_density = 0.0;
  int64_t assigned = 0;
  for (auto _ : state) {
    GnnTracker tracker(o);
    std::vector<GnnTrackRow> rows;
    assigned = 0;
    for (std::size_t k = 0; k < scene.x.size(); ++k)
      assigned += tracker.step(static_cast<double>(k), scene.x[k], scene.y[k], rows).assigned;
    benchmark::DoNotOptimize(rows.data());
  }
  state.counters["assigned"] = static_cast<double>(assigned);
  state.counters["targets"] = n;
}

BENCHMARK(BM_GnnTracker)
    ->ArgsProduct({{250, 1000, 2000}, {0, 1}})
    ->ArgNames({"targets", "sparse"})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace trackassoc

BENCHMARK_MAIN();
