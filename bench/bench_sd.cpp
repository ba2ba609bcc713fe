// Benchmarks of the S-D association (engine/pipeline/pipeline_sd.hpp), 1 and 2 threads (last Arg):
//  - BM_SDProblem/S/threads: alignment, the S(S−1)/2 pairwise statistics and the dense S-D tensor.
//  - BM_SDLagrangian/S/threads: lr+ls on it until a 0.1 % gap or 300 iterations; counters:
//    iterations, final relative gap.
//  - BM_ChnnPseudo/gated/threads: seed 004's CHNN with pseudo-tracks, with Eq. 12's gate (1) or
//    Eq. 7 only (0); counters: neurons, Euler steps. The S = 4 case only.
// Input: the embedded `seed004_25` scenario (25 dense crossing targets, four asynchronous 3-D
// radars, 200 s), simulated once with seed 1; S = 5 adds a fifth radar at (100, −50, 0) km.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <map>

#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "engine/solvers/chnn_pseudo_solver.hpp"
#include "kernels/assignment/sd/lagrangian_sd.hpp"

namespace trackassoc::bench {
namespace {

const TrackFile& track_file(int S) {
  static std::map<int, TrackFile> files;
  auto it = files.find(S);
  if (it != files.end()) return it->second;
  Scenario sc = load_scenario("seed004_25");
  if (S == 5) {
    Sensor extra = sc.sensors.back();
    extra.id = 4;
    extra.position = {100000.0, -50000.0, 0.0};
    extra.period = 3.5;
    extra.offset = 0.9;
    sc.sensors.push_back(extra);
  }
  return files.emplace(S, simulation_to_track_file(sc, simulate(sc, 1, 0))).first->second;
}

const SDProblem& problem(int S) {
  static std::map<int, SDProblem> problems;
  auto it = problems.find(S);
  if (it != problems.end()) return it->second;
  return problems.emplace(S, build_sd_problem(track_file(S), PipelineOptions{})).first->second;
}

void BM_SDProblem(benchmark::State& state) {
  const int S = static_cast<int>(state.range(0));
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(1));
  const TrackFile& f = track_file(S);
  for (auto _ : state) benchmark::DoNotOptimize(build_sd_problem(f, PipelineOptions{}).tensor.cost.data());
  state.counters["entries"] = static_cast<double>(problem(S).tensor.cost.size());
}

void BM_SDLagrangian(benchmark::State& state) {
  const int S = static_cast<int>(state.range(0));
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(1));
  const SDProblem& p = problem(S);
  LagrangianOptions o;
  o.local_search = true;
  SolutionSD s;
  for (auto _ : state) s = solve_lagrangian_sd(p.tensor, o);
  state.counters["iterations"] = static_cast<double>(s.summary.iterations);
  state.counters["gap"] = s.summary.gap;
}

void BM_ChnnPseudo(benchmark::State& state) {
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, state.range(1));
  const SDProblem& p = problem(4);
  const nlohmann::json options{{"gated", state.range(0) == 1}};
  ChnnPseudoResult raw;
  for (auto _ : state)
    benchmark::DoNotOptimize(solve_chnn_sd(sd_problem_view(p), options, 1, &raw).tuples.data());
  state.counters["neurons"] = static_cast<double>(raw.neurons);
  state.counters["steps"] = static_cast<double>(raw.steps);
}

BENCHMARK(BM_SDProblem)->ArgsProduct({{4, 5}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SDLagrangian)->ArgsProduct({{4, 5}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ChnnPseudo)->ArgsProduct({{1, 0}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace trackassoc::bench
BENCHMARK_MAIN();
