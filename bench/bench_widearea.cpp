// Benchmark of `associate` on a radar network's recording (issue 31 item 6; docs/design.md §4.10):
// the whole default association as the CLI runs it — the recycled-number split, then the
// TrackAssociator (alignment, candidates, statistics, components, solve, segments, stitching,
// registration) — on the wide-area scenarios simulated once with seed 1; 1 and 2 threads (last Arg):
//  - BM_WideAreaAssociation/0/threads: `widearea_small` (16 radars 450 km apart, 2 h, 700 targets
//    alive, ~3 × 10⁴ local tracks, 0.6 M rows; simulates in ~2 s);
//  - BM_WideAreaAssociation/1/threads: `widearea` (the same network with 7 000 alive: ~3 × 10⁵ local
//    tracks, 6 × 10⁶ rows, ~5 GB at its peak), run only when the environment sets
//    TRACKASSOC_BENCH_WIDEAREA=1 (it takes minutes); skipped with that message otherwise.
//  - BM_WideAreaStitching/threads: the stitching stage alone on `widearea_small` (below).
// Counters: each stage's seconds (<stage>_s, from AssociationSummary::stages), the process's peak
// resident memory so far (peak_rss_mib: the simulated file included, as `associate` holds its
// input; the cases run in the order above, so a case's figure also bounds the ones before), and what the
// association is worth (evaluate's figures on the output): the correct rate, the coexisting cross-radar pairs
// and the same-radar fragment pairs linked, and the pair precision (engine/pipeline/pair_metrics.hpp).
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <cstdlib>
#include <map>
#include <string>

#include "bench/simulated_files.hpp"
#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pair_metrics.hpp"
#include "engine/simulation/simulation.hpp"

namespace trackassoc::bench {
namespace {

const char* const kScenarios[] = {"widearea_small", "widearea"};

const TrackFile& track_file(int k) { return simulated_track_file(kScenarios[k]); }

void BM_WideAreaAssociation(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  if (k == 1 && !std::getenv("TRACKASSOC_BENCH_WIDEAREA")) {
    state.SkipWithError(
        "widearea: set TRACKASSOC_BENCH_WIDEAREA=1 (about a minute a run and 2 GB, plus the simulation)");
    return;
  }
  const TrackFile& recorded = track_file(k);
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(1));
  const AssociatorOptions options;
  const auto associator = make_associator(options);
  AssociationOutcome outcome;
  TrackFile file;
  for (auto _ : state) {
    state.PauseTiming();
    file = recorded;  // the split works in place, as on the file `associate` read
    state.ResumeTiming();
    outcome.summary.split = split_recorded_keys(file, options);
    outcome = associator->associate(file);
    benchmark::DoNotOptimize(outcome.record.tuples.data());
  }
  state.SetLabel(kScenarios[k]);
  for (const StageReport& s : outcome.summary.stages) state.counters[s.name + "_s"] = s.seconds;
  state.counters["peak_rss_mib"] = peak_rss_mib();
  const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, outcome.record);
  const PairMetrics pairs = evaluate_pairs(file.tracks, file.sensors, outcome.record);
  state.counters["correct_rate"] = m.correct_rate;
  state.counters["coexisting_linked"] = pairs.coexisting_recall;
  state.counters["fragments_linked"] = pairs.fragment_recall;
  state.counters["pair_precision"] = pairs.precision;
}

// Fragment stitching alone (engine/pipeline/track_stitching.hpp) on `widearea_small`: the default
// association without it, made once, then stitch_fragments on a fresh copy of its record each
// iteration (the copy untimed), 1 and 2 threads. Counters: groups, gated continuations and joins
// made, and the learnt manoeuvre weight.
void BM_WideAreaStitching(benchmark::State& state) {
  struct Unstitched {
    TrackFile file;
    AssociationRecord record;
  };
  static const Unstitched unstitched = [] {
    Unstitched u{track_file(0), {}};
    AssociatorOptions options;
    options.stitching.enabled = false;
    split_recorded_keys(u.file, options);
    u.record = make_associator(options)->associate(u.file).record;
    return u;
  }();
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(0));
  const TrackStitchOptions options;
  TrackStitchSummary summary;
  AssociationRecord record;
  for (auto _ : state) {
    state.PauseTiming();
    record = unstitched.record;
    state.ResumeTiming();
    summary = stitch_fragments(unstitched.file, record, options);
    benchmark::DoNotOptimize(record.tuples.data());
  }
  state.counters["groups"] = summary.groups;
  state.counters["candidates"] = summary.candidates;
  state.counters["stitches"] = summary.stitches;
  state.counters["turn_probability"] = summary.turn_probability;
}

BENCHMARK(BM_WideAreaStitching)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_WideAreaAssociation)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace trackassoc::bench

BENCHMARK_MAIN();
