// Benchmarks of the default pipeline for recorded track sets (engine/pipeline/sparse_sd_pipeline.hpp), on
// the embedded realistic-recording family, simulated once with seed 1; 1 and 2 threads (last Arg):
//  - BM_DefaultAssociation/scenario/threads: `associate` without flags, from the loaded file to the
//    tuples (alignment, candidates, statistic, components, lr+ls per component).
//    scenario 0 = recorded_3s (3 sensors), 1 = recorded_5s (5 sensors × 60 targets, the issue 20
//    goal: ≤ 1 s), 2 = recorded_dense, 3 = recorded_10k (3 × 10 000 targets, the sparse scale),
//    4 = recorded_sync (synchronous sensors: the one file where Stone Soup's associator, which
//    compares tracks only at shared timestamps, is a peer; scripts/bench.sh runs
//    bench/stonesoup_t2t.py on `trackassoc simulate --scenario recorded_sync --seed 1`, the same file),
//    5 = recorded_30k (recorded_10k at three times its density: giant components, solved over their
//    listed tuples, engine/pipeline/sparse_sd_tuples.hpp).
//  - BM_DenseSDAssociation/threads: the dense S-D tensor with dummies on recorded_5s (the path that
//    took 20–34 s before issue 20), lr+ls: the naive version of the same problem.
//  - BM_AutoferryExperiment/threads: `experiment autoferry` on the 9 real Autoferry scenarios
//    (../shared/datasets/autoferry): detections → local tracks → default association → scoring,
//    without writing files (issue 17's goal: the whole set in ≤ 10 s; it was an assertion in
//    tests/engine/studies/test_autoferry.cpp, where a loaded machine could fail it).
// Counters: candidate pairs, gated pairs, components; components solved over listed tuples, the
// largest list, the largest per-component relative gap and the merging fallbacks.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <filesystem>
#include <map>

#include "bench/simulated_files.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/studies/autoferry/autoferry.hpp"

namespace trackassoc::bench {
namespace {

const char* const kScenarios[] = {"recorded_3s",  "recorded_5s",   "recorded_dense",
                                  "recorded_10k", "recorded_sync", "recorded_30k"};

const TrackFile& track_file(int k) { return simulated_track_file(kScenarios[k]); }

void BM_DefaultAssociation(benchmark::State& state) {
  const TrackFile& file = track_file(static_cast<int>(state.range(0)));
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(1));
  SparseSDReport report;
  for (auto _ : state) {
    const AssociationRecord rec =
        associate_sparse_sd(file, "lr+ls", nlohmann::json::object(), 1, SparseSDOptions{}, &report);
    benchmark::DoNotOptimize(rec.tuples.data());
  }
  state.SetLabel(kScenarios[state.range(0)]);
  state.counters["candidate_pairs"] = static_cast<double>(report.solve.candidate_pairs);
  state.counters["gated_pairs"] = static_cast<double>(report.solve.gated_pairs);
  state.counters["components"] = report.solve.components;
  state.counters["listed_components"] = report.solve.listed_components;
  state.counters["largest_listed_tuples"] = static_cast<double>(report.solve.largest_listed_tuples);
  state.counters["largest_gap"] = report.solve.largest_component_gap;
  state.counters["fallback_components"] = report.solve.fallback_components;
}

void BM_DenseSDAssociation(benchmark::State& state) {
  const TrackFile& file = track_file(1);
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(0));
  for (auto _ : state) {
    const SDProblem p = build_sd_problem(file, PipelineOptions{});
    const AssociationRecord rec =
        solve_sd_association(p, "lr+ls", nlohmann::json::object(), 1, PipelineOptions{});
    benchmark::DoNotOptimize(rec.tuples.data());
  }
}

void BM_AutoferryExperiment(benchmark::State& state) {
  const std::string root = std::string(TRACKASSOC_SHARED_DIR) + "/datasets/autoferry";
  if (!std::filesystem::exists(root + "/scenario1")) {
    state.SkipWithError(("Autoferry data absent: " + root).c_str());
    return;
  }
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(0));
  AutoferryExperimentResult res;
  for (auto _ : state) {
    res = run_autoferry_experiment(root, AutoferryOptions{}, "");
    benchmark::DoNotOptimize(res.total.correct);
  }
  state.counters["precision"] = res.total.precision();
  state.counters["recall"] = res.total.recall();
}

BENCHMARK(BM_DefaultAssociation)
    ->ArgsProduct({{0, 1, 2, 4}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_DefaultAssociation)
    ->ArgsProduct({{3, 5}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK(BM_DenseSDAssociation)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_AutoferryExperiment)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
