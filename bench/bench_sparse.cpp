// The sparse association path (issue 6) at n = 10², 10³, 10⁴ targets per sensor, 1 and 2 threads:
//   candidates  — grid index (ours) vs the all-pairs scan of the same bound (naive peer);
//   statistic   — λ on candidate pairs (ours) vs the dense all-pairs statistic (peer, n ≤ 10³);
//   problem     — alignment + candidates + λ + components, end to end;
//   solve       — components solved in parallel with the registry's "pairwise" solver.
//   problem, defaults — the same problem with `associate --sparse`'s default options (n ≤ 10³),
//                       the same with only the gate changed to seed 000's (its time-averaged
//                       index), the same with the alignment's lag terms forced, and the default path's
//                       problem with those options (the same pair source); then on
//                       recorded_10k's filtered tracks, the defaults against seed 000's options.
//   candidates by density — the candidates stage alone for both gates at the scale study's density
//                       (n = 10³ and 10⁴) and at a tenth of it (n = 10³);
//   wide-area candidates — the default path's candidate index (engine/pipeline/pair_source.hpp) over
//                       widearea_small's 16 radars (seed 1), every pair of sensors at once (issue 31).
// Track sets: engine/studies/scale/experiment_scale.hpp's synthetic_recorded_tracks at the experiment's
// default density (100 targets per 100 km², 3-D) and options (PipelineOptions::paper()). Args: {n, threads}
// (the recorded_10k and wide-area cases: {threads}).
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <limits>
#include <map>
#include <memory>

#include "bench/simulated_files.hpp"
#include "engine/pipeline/pair_source.hpp"
#include "engine/pipeline/pipeline.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/studies/scale/experiment_scale.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {
namespace {

struct Fixture {
  TrackFile file;
  std::vector<AlignedTracks> aligned;
  CandidatePairs c12;
  std::unique_ptr<SparseAssociationProblem> problem;
};

// The scale study's options (`experiment scale`, engine/studies/scale/experiment_scale.cpp): the
// χ²(n·D) gate of seed 000 with forward alignment, for which the index's bound was derived.
SparsePipelineOptions pipeline_options() {
  SparsePipelineOptions o;
  o.pipeline = PipelineOptions::paper();
  o.pipeline.statistic.gate_probability = 0.999;
  return o;
}

// The scale study's tracks of n targets a sensor (seed 42), at `density_scale` times its density.
TrackFile scale_study_tracks(int32_t n, double density_scale = 1.0) {
  ScaleExperimentOptions defaults;
  SyntheticTrackSpec spec = defaults.tracks;
  spec.targets = n;
  spec.box = std::sqrt(n / (defaults.density * density_scale)) * 10000.0;
  spec.seed = 42;
  return synthetic_recorded_tracks(spec);
}

const Fixture& fixture(int32_t n) {
  static std::map<int32_t, std::unique_ptr<Fixture>> cache;
  auto& f = cache[n];
  if (!f) {
    f = std::make_unique<Fixture>();
    f->file = scale_study_tracks(n);
    const auto o = pipeline_options();
    f->problem = std::make_unique<SparseAssociationProblem>(build_sparse_association_problem(f->file, o));
    f->aligned = f->problem->aligned;
    f->c12 = gated_candidate_pairs(f->aligned[0], f->aligned[1], CandidateOptions{0.999, 1.0});
  }
  return *f;
}

// The thread count is the argument `arg` ({n, threads}: 1).
void set_threads(benchmark::State& state, std::unique_ptr<tbb::global_control>& gc, int arg = 1) {
  gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                             static_cast<std::size_t>(state.range(arg)));
}

void BM_SparseCandidates(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  std::size_t pairs = 0;
  for (auto _ : state) {
    const CandidatePairs c = gated_candidate_pairs(f.aligned[0], f.aligned[1], CandidateOptions{0.999, 1.0});
    pairs = c.size();
    benchmark::DoNotOptimize(c.a.data());
  }
  state.counters["candidates"] = static_cast<double>(pairs);
  state.counters["tracks_per_s"] =
      benchmark::Counter(2.0 * state.range(0), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_AllPairsCandidates(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  for (auto _ : state) {
    const CandidatePairs c =
        gated_candidate_pairs_all_pairs(f.aligned[0], f.aligned[1], CandidateOptions{0.999, 1.0});
    benchmark::DoNotOptimize(c.a.data());
  }
  state.counters["tracks_per_s"] =
      benchmark::Counter(2.0 * state.range(0), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_SparseStatistic(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  StatisticOptions so;
  so.gate_probability = 0.999;
  for (auto _ : state) {
    const SparsePairStatistic s = sparse_sequential_statistic(f.aligned[0], f.aligned[1], f.c12, so);
    benchmark::DoNotOptimize(s.lambda.data());
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(f.c12.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_DenseStatistic(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  StatisticOptions so;
  so.gate_probability = 0.999;
  for (auto _ : state) {
    const PairStatistic s = independent_sequential_statistic(f.aligned[0], f.aligned[1], so);
    benchmark::DoNotOptimize(s.lambda.data());
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(state.range(0)) * state.range(0),
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

void BM_SparseProblem(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  const auto o = pipeline_options();
  std::size_t gated = 0;
  std::vector<StageReport> stages;
  for (auto _ : state) {
    const SparseAssociationProblem p = build_sparse_association_problem(f.file, o);
    gated = p.s12.size();
    stages = p.stages;
    benchmark::DoNotOptimize(p.components.count);
  }
  state.counters["gated_12"] = static_cast<double>(gated);
  for (const StageReport& s : stages) state.counters[s.name + "_s"] = s.seconds;
  state.counters["tracks_per_s"] =
      benchmark::Counter(3.0 * state.range(0), benchmark::Counter::kIsIterationInvariantRate);
}

// Builds a sparse problem of `file` per iteration, on the threads of argument `threads_arg`;
// counters: the candidate pairs of sensors 1–2 (its slot `slot12`), the gated pairs 1–2 of a
// three-sensor problem, and the last iteration's stage times.
template <class Build>
void build_problems(benchmark::State& state, const TrackFile& file, std::size_t slot12, Build build,
                    int threads_arg = 1) {
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc, threads_arg);
  std::size_t candidates = 0, gated = 0;
  std::vector<StageReport> stages;
  for (auto _ : state) {
    const auto p = build(file);
    candidates = p.candidate_pairs[slot12];
    if constexpr (requires { p.s12; }) gated = p.s12.size();
    stages = p.stages;
    benchmark::DoNotOptimize(p.components.count);
  }
  state.counters["candidates_12"] = static_cast<double>(candidates);
  if (gated > 0) state.counters["gated_12"] = static_cast<double>(gated);
  for (const StageReport& s : stages) state.counters[s.name + "_s"] = s.seconds;
}

// The same problem with `associate --sparse`'s default options (calibrated gate, p = 0.999), each
// variant below changing one of them (`change`).
void defaults_problem(benchmark::State& state, void (*change)(SparsePipelineOptions&)) {
  SparsePipelineOptions o;
  o.pipeline.statistic.gate_probability = 0.999;
  change(o);
  build_problems(state, fixture(static_cast<int32_t>(state.range(0))).file, 0,
                 [&](const TrackFile& file) { return build_sparse_association_problem(file, o); });
}

// The defaults: the candidate count and time those options cost at this density (counter: candidate
// pairs 1–2).
void BM_SparseProblemDefaults(benchmark::State& state) {
  defaults_problem(state, [](SparsePipelineOptions&) {});
}

// Seed 000's χ²(n·D) gate in place of the calibrated one, nothing else changed (the same alignment
// and statistic): the time-averaged index of kernels/statistics/sparse_candidates.hpp against the
// per-scan one (docs/performance.md, "Session 33").
void BM_SparseProblemDefaultsSeed000Gate(benchmark::State& state) {
  defaults_problem(state,
                   [](SparsePipelineOptions& o) { o.pipeline.statistic.gate = GateMethod::kChiSquareSum; });
}

// The alignment's two lag terms forced on (AlignmentOptions::whiteness_threshold +inf), as they were
// before the whiteness test (kernels/statistics/report_whiteness.hpp): these tracks are reports with
// independent noise, not a filter's output, so the test leaves the terms out; forced, their velocity
// jumps read as manoeuvres and widen some reports' covariances by kilometres (lag time τ² =
// P_pp/P_vv = 225 s² here, τ = 15 s). The counters show what that widening costs the index.
void BM_SparseProblemDefaultsLagForced(benchmark::State& state) {
  defaults_problem(state, [](SparsePipelineOptions& o) {
    o.pipeline.alignment.whiteness_threshold = std::numeric_limits<double>::infinity();
  });
}

// The default (sparse S-D) path's problem with the same options on the same tracks: the index and
// pair source that `--sparse` shares (engine/pipeline/pair_source.hpp).
void BM_DefaultPathProblem(benchmark::State& state) {
  SparseSDOptions o;
  o.pipeline.statistic.gate_probability = 0.999;
  build_problems(state, fixture(static_cast<int32_t>(state.range(0))).file, 1,
                 [&](const TrackFile& file) { return build_sparse_sd_problem(file, o); });  // 0·S + 1
}

// The same comparison on filtered tracks: recorded_10k (3 × 10 000 targets, every local track a
// Kalman filter's output; seed 1, run 0), the problem with `--sparse`'s default options against
// seed 000's (PipelineOptions::paper()), both at the CLI's gate probability 0.99. Args: {threads}.
void BM_RecordedProblem(benchmark::State& state, bool seed000) {
  SparsePipelineOptions o;
  if (seed000) o.pipeline = PipelineOptions::paper();
  build_problems(
      state, bench::simulated_track_file("recorded_10k"), 0,
      [&](const TrackFile& file) { return build_sparse_association_problem(file, o); }, 0);
}

void BM_SparseSolve(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int32_t>(state.range(0)));
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc);
  const auto o = pipeline_options();
  for (auto _ : state) {
    const AssociationRecord r =
        solve_sparse_association(*f.problem, "pairwise", nlohmann::json::object(), 1, o);
    benchmark::DoNotOptimize(r.tuples.data());
  }
  state.counters["components"] = static_cast<double>(f.problem->components.count);
}

// The candidates stage of `associate` on widearea_small (seed 1): the index over all 120 pairs of
// its 16 radars and the position-bound prune. Counters: pairs found, pairs kept.
void BM_WideAreaCandidates(benchmark::State& state) {
  static const AlignedSensors sensors = [] {
    const Scenario sc = load_scenario("widearea_small");
    const TrackFile file = simulation_to_track_file(sc, simulate(sc, 1, 0));
    return align_sensors(file, PipelineOptions{}, SensorRule::kTwoOrMore, EmptySensors::kLeaveOut);
  }();
  tbb::global_control g(tbb::global_control::max_allowed_parallelism,
                        static_cast<std::size_t>(state.range(0)));
  std::size_t found = 0, kept = 0;
  for (auto _ : state) {
    const std::vector<IndexedCandidates> c = indexed_candidates(sensors, StatisticOptions{}, 1.0);
    found = kept = 0;
    for (const auto& x : c) {
      found += x.found;
      kept += x.pairs.size();
    }
    benchmark::DoNotOptimize(c.data());
  }
  state.counters["found"] = static_cast<double>(found);
  state.counters["kept"] = static_cast<double>(kept);
}

// The candidates stage alone (engine/pipeline/pair_source.hpp: the index, then the prune) on the
// scale study's tracks at n = 1000 and 10 000, at its density (and at a tenth of it for n = 1000),
// for `--sparse`'s calibrated gate (the per-scan index, whose grid cells are widened for sparse
// tracks, kernels/statistics/scan_search.cpp) and for seed 000's (the time-averaged index). Args:
// {n, density in tenths of the study's, gate (0 calibrated, 1 seed 000), threads}. Counter: the
// pairs kept.
void BM_CandidatesByDensity(benchmark::State& state) {
  static std::map<std::pair<int64_t, int64_t>, std::unique_ptr<TrackFile>> files;
  auto& file = files[{state.range(0), state.range(1)}];
  if (!file)
    file = std::make_unique<TrackFile>(
        scale_study_tracks(static_cast<int32_t>(state.range(0)), static_cast<double>(state.range(1)) / 10.0));
  PipelineOptions o;
  o.statistic.gate_probability = 0.999;
  if (state.range(2) == 1) o.statistic.gate = GateMethod::kChiSquareSum;
  // Aligned at each call, beside the file, as `associate` does before its candidates stage (aligned
  // once and kept for every call and both gates, the calibrated gate's stage, whose count filter
  // reads cells at random, measured 176–178 against 168–170 ms at n = 10 000 and seed 000's the same:
  // where the cells lie in memory matters; docs/performance.md "Session 38").
  const AlignedSensors sensors = align_sensors(*file, o, SensorRule::kThree, EmptySensors::kRefuse);
  std::unique_ptr<tbb::global_control> gc;
  set_threads(state, gc, 3);
  std::size_t kept = 0;
  for (auto _ : state) {
    const std::vector<IndexedCandidates> c = indexed_candidates(sensors, o.statistic, 1.0);
    kept = 0;
    for (const auto& x : c) kept += x.pairs.size();
    benchmark::DoNotOptimize(c.data());
  }
  state.counters["kept"] = static_cast<double>(kept);
}

void sizes(benchmark::internal::Benchmark* b, int64_t max_n) {
  for (int64_t n : {100, 1000, 10000})
    if (n <= max_n)
      for (int64_t t : {1, 2}) b->Args({n, t});
  b->ArgNames({"n", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

// BM_CandidatesByDensity's cases: {n, density in tenths, gate, threads}, a tenth of the density at
// n = 1000 only.
void density_cases(benchmark::internal::Benchmark* b) {
  for (int64_t n : {1000, 10000})
    for (int64_t density : {10, 1})
      if (density == 10 || n == 1000)
        for (int64_t gate : {0, 1})
          for (int64_t t : {1, 2}) b->Args({n, density, gate, t});
  b->ArgNames({"n", "density_tenths", "gate", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_SparseCandidates)->Apply([](auto* b) { sizes(b, 10000); });
BENCHMARK(BM_AllPairsCandidates)->Apply([](auto* b) { sizes(b, 10000); });
BENCHMARK(BM_SparseStatistic)->Apply([](auto* b) { sizes(b, 10000); });
BENCHMARK(BM_DenseStatistic)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK(BM_SparseProblem)->Apply([](auto* b) { sizes(b, 10000); });
BENCHMARK(BM_SparseProblemDefaults)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK(BM_SparseProblemDefaultsSeed000Gate)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK(BM_SparseProblemDefaultsLagForced)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK(BM_DefaultPathProblem)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK_CAPTURE(BM_RecordedProblem, defaults, false)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RecordedProblem, seed000, true)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_SparseSolve)->Apply([](auto* b) { sizes(b, 10000); });
BENCHMARK(BM_CandidatesByDensity)->Apply(density_cases);
BENCHMARK(BM_WideAreaCandidates)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace trackassoc

BENCHMARK_MAIN();
