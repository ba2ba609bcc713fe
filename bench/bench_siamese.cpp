// Siamese BiLSTM (seed 003): training-step throughput for 1 vs 2 threads, and inference at track
// density 80 — embed-once + head (ours) vs recomputing both branches per pair (the paper's way).
// The weights are freshly initialised (speed does not depend on their values); H = 64, fc = 512.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <numeric>

#include "engine/pipeline/siamese_pipeline.hpp"
#include "engine/studies/seed003/dataset_seed003.hpp"
#include "kernels/learning/siamese_training.hpp"

using namespace trackassoc;

namespace {

SiameseModel<float> paper_model() {
  SiameseModel<float> m;  // H = 64, fc = 512 (seed 003)
  siamese_initialise(m, 1);
  return m;
}

const Seed003Scene& scene(int n) {
  static Seed003Scene s80 = simulate_seed003_scene(Seed003Options{}, 80, 0);
  static Seed003Scene s256 = simulate_seed003_scene(Seed003Options{}, 256, 1);
  return n == 80 ? s80 : s256;
}

// One Adam step on a mini-batch of 64 pairs (32 positive, 32 negative), chunks of 16 pairs.
void BM_SiameseTrainingStep(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(0)));
  const Seed003Scene& s = scene(256);
  SiameseModel<float> model = paper_model();
  std::vector<int32_t> l(64), r(64);
  std::vector<uint8_t> y(64);
  for (int k = 0; k < 64; ++k) {
    l[k] = k;
    r[k] = k % 2 ? k : (k + 7) % 256;
    y[k] = k % 2;
  }
  AdamState<float> adam;
  SiameseStepWorkspace<float> ws;
  const AdamOptions ao;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        siamese_minibatch_step<float>(model, s.radar1, s.radar2, l, r, y, 16, adam, ao, ws));
  }
  state.counters["pairs_per_s"] = benchmark::Counter(64.0 * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["threads"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_SiameseTrainingStep)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Embed the 80 + 80 tracks once, then the head on all 6400 pairs (no LAP).
void BM_SiameseScoreEmbedOnce(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(0)));
  const Seed003Scene& s = scene(80);
  const SiameseModel<float> model = paper_model();
  std::vector<float> prob(80 * 80);
  for (auto _ : state) {
    const MatrixX<float> e1 = embed_tracks(model, s.radar1), e2 = embed_tracks(model, s.radar2);
    siamese_score_all_pairs<float>(model, e1, e2, prob);
    benchmark::DoNotOptimize(prob.data());
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(6400.0 * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["threads"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_SiameseScoreEmbedOnce)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The paper's way: both branches recomputed for every one of the 6400 pairs.
void BM_SiameseScorePerPair(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(0)));
  const Seed003Scene& s = scene(80);
  const SiameseModel<float> model = paper_model();
  std::vector<float> prob(80 * 80);
  for (auto _ : state) {
    score_pairs_recomputing(model, s.radar1, s.radar2, prob);
    benchmark::DoNotOptimize(prob.data());
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(6400.0 * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["threads"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_SiameseScorePerPair)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The whole association at density 80: embed, score, thresholded LAP.
void BM_SiameseAssociate(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(0)));
  const Seed003Scene& s = scene(80);
  const SiameseModel<float> model = paper_model();
  for (auto _ : state) benchmark::DoNotOptimize(associate_siamese(model, s.radar1, s.radar2, {}));
  state.counters["pairs_per_s"] =
      benchmark::Counter(6400.0 * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["threads"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_SiameseAssociate)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
