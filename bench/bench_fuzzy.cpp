// Seed 001 fusion centres and the alpha-beta bank.
//   BM_FuzzyAssociation/J  — the proposed method's time per packet with J targets (J system tracks
//                            live), 4 sensors reporting every 4 s, staggered
//                            (tests/support/fuzzy_test_scenes.hpp).
//   BM_Ftaa/J              — the FTAA baseline on the same stream (the peer).
//   BM_AlphaBetaBank/n/thr — one scan (predict + update) of a 2-D bank of n tracks, 1 vs 2 threads.
//   BM_AlphaBetaPerTrack/n — the same scan as n per-track calls (the naive loop).
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/filters/alpha_beta.hpp"
#include "kernels/fuzzy/ftaa.hpp"
#include "kernels/fuzzy/fuzzy_association.hpp"
#include "tests/support/fuzzy_test_scenes.hpp"

using namespace trackassoc;

namespace {

// J targets on a square grid 10 km apart, flying east at 250 m/s: J well-separated system tracks.
test_scenes::Scene grid_scene(int J, double duration) {
  std::vector<std::array<double, 4>> targets;
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(J))));
  for (int k = 0; k < J; ++k) targets.push_back({10000.0 * (k % side), 10000.0 * (k / side), 250.0, 0.0});
  return test_scenes::make_scene(17, 0, targets, duration);
}

void BM_FuzzyAssociation(benchmark::State& state) {
  const int J = static_cast<int>(state.range(0));
  const auto scene = grid_scene(J, 40.0);
  const FuzzyAssociationOptions options;
  int64_t tracks = 0;
  for (auto _ : state) {
    const FusionOutput out =
        run_fuzzy_association(scene.spans(), scene.reliability, scene.num_local, options);
    tracks = out.num_system_tracks;
    benchmark::DoNotOptimize(out.x.data());
  }
  const double packets = static_cast<double>(scene.size());
  state.counters["system_tracks"] = static_cast<double>(tracks);
  state.counters["packets"] = packets;
  state.counters["us_per_packet"] = benchmark::Counter(
      packets * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FuzzyAssociation)
    ->Arg(10)
    ->Arg(30)
    ->Arg(100)
    ->Arg(300)
    ->Arg(1000)
    ->Unit(benchmark::kMillisecond);

void BM_Ftaa(benchmark::State& state) {
  const int J = static_cast<int>(state.range(0));
  const auto scene = grid_scene(J, 40.0);
  const FtaaOptions options;
  for (auto _ : state) {
    const FtaaResult r = run_ftaa(scene.spans(), 4, scene.num_local, options);
    benchmark::DoNotOptimize(r.fusion.x.data());
  }
  const double packets = static_cast<double>(scene.size());
  state.counters["packets"] = packets;
  state.counters["us_per_packet"] = benchmark::Counter(
      packets * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Ftaa)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)->Unit(benchmark::kMillisecond);

struct BankInput {
  std::vector<double> zx, zy;
  std::vector<uint8_t> detected;
};
BankInput bank_input(std::size_t n) {
  BankInput in;
  CounterRng rng(21);
  in.zx.resize(n);
  in.zy.resize(n);
  in.detected.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    in.zx[i] = rng.normal(0, 100);
    in.zy[i] = rng.normal(0, 100);
    in.detected[i] = rng.uniform() < 0.9;
  }
  return in;
}

void BM_AlphaBetaBank(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(state.range(1)));
  AlphaBetaBank bank(2, n, AlphaBetaOptions{});
  const BankInput in = bank_input(n);
  const std::vector<std::span<const double>> z{in.zx, in.zy};
  for (auto _ : state) {
    bank.predict(1.0);
    bank.update(z, in.detected);
    benchmark::ClobberMemory();
  }
  state.counters["updates_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlphaBetaBank)
    ->Args({1 << 20, 1})
    ->Args({1 << 20, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_AlphaBetaPerTrack(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  AlphaBetaBank bank(2, n, AlphaBetaOptions{});
  const BankInput in = bank_input(n);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      bank.predict_track(i, 1.0);
      if (in.detected[i]) {
        const double z[2] = {in.zx[i], in.zy[i]};
        bank.update_track(i, z);
      }
    }
    benchmark::ClobberMemory();
  }
  state.counters["updates_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlphaBetaPerTrack)->Arg(1 << 20)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
