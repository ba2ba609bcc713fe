// Hopfield sweep and restart speed (docs/design.md §6), with the floors measured in the same binary:
//   - a STREAM-style copy (1 and 2 threads) gives the memory bandwidth; a sweep's memory floor is
//     12 B per neuron (docs/design.md §6) at that bandwidth, reported as counter floor_ratio = time/floor;
//   - the naive n⁶-weight network (kernels/hopfield/hopfield_energy.hpp) is the peer of the marginal-sum
//     sweep at n = 10–15.
// Thread variants use tbb::global_control with the thread count as the last Arg.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <numeric>
#include <vector>

#include "kernels/core/parallel.hpp"
#include "kernels/core/stopwatch.hpp"
#include "kernels/hopfield/hopfield.hpp"
#include "kernels/hopfield/hopfield_continuous.hpp"
#include "kernels/hopfield/hopfield_diagonal.hpp"
#include "kernels/hopfield/hopfield_discrete.hpp"
#include "tests/support/hopfield_instances.hpp"

using namespace trackassoc;

namespace {

constexpr double kFloorBytesPerNeuron = 12.0;  // docs/design.md §6
double g_copy_bandwidth[3] = {0, 0, 0};        // bytes/s moved (read + write), by thread count

// STREAM "copy": b[i] = a[i] over 64 MiB arrays (beyond the 32 MB L3), parallel over blocks.
double stream_copy_seconds(std::vector<float>& a, std::vector<float>& b) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = a.size(), block = std::size_t{1} << 16;
  parallel_for_range((n + block - 1) / block, 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t blk = lo; blk < hi; ++blk) {
      const std::size_t s = blk * block, e = std::min(n, s + block);
      std::memcpy(b.data() + s, a.data() + s, (e - s) * sizeof(float));
    }
  });
  return seconds_since(t0);
}

void measure_copy_bandwidth() {
  std::vector<float> a(std::size_t{16} << 20, 1.f), b(a.size(), 0.f);
  for (int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    double best = 1e9;
    for (int rep = 0; rep < 10; ++rep) best = std::min(best, stream_copy_seconds(a, b));
    g_copy_bandwidth[threads] = 2.0 * a.size() * sizeof(float) / best;
  }
}

void BM_StreamCopy(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(0));
  std::vector<float> a(std::size_t{16} << 20, 1.f), b(a.size(), 0.f);
  for (auto _ : state) benchmark::DoNotOptimize(stream_copy_seconds(a, b));
  state.counters["GB/s"] =
      benchmark::Counter(2.0 * a.size() * sizeof(float), benchmark::Counter::kIsIterationInvariantRate,
                         benchmark::Counter::kIs1000);
}
BENCHMARK(BM_StreamCopy)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

struct Fixture {
  GeometricInstance inst;
  NormalisedCost c;
  HopfieldWeights w;
  std::vector<uint8_t> V0;  // the true association: a valid state
  explicit Fixture(int32_t n) {
    GeometricInstanceOptions o;
    o.n = n;
    inst = make_geometric_instance(o, 7);
    c = normalise_cost(inst.cost);
    w = HopfieldWeights{1, 1, 1, 0, 1.4f, n};
    V0.assign(c.size(), 0);
    for (const auto& t : inst.truth) V0[inst.cost.index(t[0], t[1], t[2])] = 1;
  }
};

// Runs `sweep` in the benchmark loop and reports neurons/s, the memory floor (12 B per neuron at
// the copy bandwidth measured for this thread count) and floor_ratio = time per sweep / floor.
template <class Sweep>
void run_with_floor(benchmark::State& state, std::size_t neurons, int threads, Sweep&& sweep) {
  double total = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    sweep();
    total += seconds_since(t0);
  }
  const double floor_s = kFloorBytesPerNeuron * neurons / g_copy_bandwidth[std::min(threads, 2)];
  state.counters["neurons/s"] =
      benchmark::Counter(static_cast<double>(neurons), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["floor_ms"] = floor_s * 1e3;
  state.counters["floor_ratio"] = total / static_cast<double>(state.iterations()) / floor_s;
}

void BM_SyncSweep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Fixture f(n);
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, f.w, f.c);
  net.set_state(f.V0);
  run_with_floor(state, f.c.size(), threads, [&] { benchmark::DoNotOptimize(sync_sweep(net).flips); });
}
BENCHMARK(BM_SyncSweep)->ArgsProduct({{50, 100, 200}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SyncSweepPrinted(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Fixture f(n);
  DiscreteNetwork net(HopfieldEnergy::kPrinted, HopfieldWeights{300, 300, 300, 200, 1100, n}, f.c);
  net.set_state(f.V0);
  run_with_floor(state, f.c.size(), threads, [&] { benchmark::DoNotOptimize(sync_sweep(net).flips); });
}
BENCHMARK(BM_SyncSweepPrinted)
    ->ArgsProduct({{50, 100, 200}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The ascending cost order of the n³ entries (the OrderedSweepPlan's input, built once per solve):
// the radix sort of kernels/core/radix_sort.hpp in parallel chunks. Args: {n, threads}.
void BM_CostOrder(benchmark::State& state) {
  const Fixture f(static_cast<int32_t>(state.range(0)));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                         static_cast<std::size_t>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(ascending_cost_order(f.c.c).data());
  state.counters["entries"] = static_cast<double>(f.c.size());
}
BENCHMARK(BM_CostOrder)->ArgsProduct({{100, 200}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

// Async: serial within a restart; the sweep includes drawing its order (Arg 1: 0 = uniform random
// permutation, 1 = slice-random order, 2 = ascending cost through the OrderedSweepPlan, the default
// solver's path, built once per solve and not timed here). The state is the true association, a
// fixed point: this is the cost of a sweep that confirms convergence (every solve ends with one).
void BM_AsyncSweep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const int64_t kind = state.range(1);
  Fixture f(n);
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, f.w, f.c);
  net.set_state(f.V0);
  std::vector<uint32_t> order(f.c.size());
  std::iota(order.begin(), order.end(), 0u);
  std::unique_ptr<OrderedSweepPlan> plan;
  if (kind == 2) plan = std::make_unique<OrderedSweepPlan>(ascending_cost_order(f.c.c), f.c);
  SliceRandomOrder so;
  CounterRng rng(1);
  run_with_floor(state, f.c.size(), 1, [&] {
    if (kind == 1) {
      so.draw(n, n, n, rng);
      benchmark::DoNotOptimize(async_sweep_slices(net, so.slices, so.packed_jk, so.rotation));
    } else if (kind == 2) {
      benchmark::DoNotOptimize(async_sweep_planned(net, *plan));
    } else {
      rng.shuffle(std::span<uint32_t>(order));
      benchmark::DoNotOptimize(async_sweep(net, order));
    }
  });
}
BENCHMARK(BM_AsyncSweep)
    ->ArgsProduct({{50, 100, 200}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A sweep that works: from a perturbed association (each true triple kept with probability 0.8,
// plus n/10 stray neurons), the state the default solver's async phase starts from after the
// mean-field start (which leaves conflicts and empty planes). Same orders as BM_AsyncSweep; the
// reset of the state is not timed. Counter flips = flips of the timed sweep.
void BM_AsyncWorkingSweep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const int64_t kind = state.range(1);
  Fixture f(n);
  CounterRng rng(5);
  std::vector<uint8_t> start(f.c.size(), 0);
  for (const auto& t : f.inst.truth)
    if (rng.uniform() < 0.8) start[f.inst.cost.index(t[0], t[1], t[2])] = 1;
  for (int32_t s = 0; s < std::max(1, n / 10); ++s) start[rng.uniform_int(start.size())] = 1;
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, f.w, f.c);
  std::vector<uint32_t> order(f.c.size());
  std::iota(order.begin(), order.end(), 0u);
  std::unique_ptr<OrderedSweepPlan> plan;
  if (kind == 2) plan = std::make_unique<OrderedSweepPlan>(ascending_cost_order(f.c.c), f.c);
  SliceRandomOrder so;
  double total = 0.0;
  int64_t flips = 0;
  for (auto _ : state) {
    net.set_state(start);
    const auto t0 = std::chrono::steady_clock::now();
    if (kind == 1) {
      so.draw(n, n, n, rng);
      flips = async_sweep_slices(net, so.slices, so.packed_jk, so.rotation);
    } else if (kind == 2) {
      flips = async_sweep_planned(net, *plan);
    } else {
      rng.shuffle(std::span<uint32_t>(order));
      flips = async_sweep(net, order);
    }
    const double dt = seconds_since(t0);
    state.SetIterationTime(dt);
    total += dt;
  }
  state.counters["flips"] = static_cast<double>(flips);
  state.counters["neurons/s"] = static_cast<double>(f.c.size()) * state.iterations() / total;
}
BENCHMARK(BM_AsyncWorkingSweep)
    ->ArgsProduct({{50, 100, 200}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

// The permutation alone, to split the async time.
void BM_AsyncPermutation(benchmark::State& state) {
  const std::size_t K = static_cast<std::size_t>(state.range(0)) * state.range(0) * state.range(0);
  std::vector<uint32_t> order(K);
  std::iota(order.begin(), order.end(), 0u);
  CounterRng rng(1);
  for (auto _ : state) {
    rng.shuffle(std::span<uint32_t>(order));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_AsyncPermutation)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

// Diagonal sweep (random block order drawn per sweep, as in the solver). Arg 1: 0 = the vector
// path (DiagonalNetwork::sweep), 1 = the scalar segment loop it replaced (sweep_reference), the
// peer in the same run. One thread, like the async sweeps: one restart's blocks follow each other
// (a block at n = 100 is ~60 ns of work, too little to hand to a thread); its parallelism is the
// vector lanes within a block, and across threads the restarts (BM_Restarts*). The layout of the
// cost is built once per solve: BM_DiagonalLayout.
void BM_DiagonalSweep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const bool reference = state.range(1) == 1;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
  Fixture f(n);
  DiagonalNetwork net(f.w, f.c);
  net.set_state(f.V0);
  std::vector<uint32_t> order(net.num_blocks());
  std::iota(order.begin(), order.end(), 0u);
  CounterRng rng(1);
  run_with_floor(state, f.c.size(), 1, [&] {
    rng.shuffle(std::span<uint32_t>(order));
    benchmark::DoNotOptimize(reference ? net.sweep_reference(order) : net.sweep(order));
  });
}
BENCHMARK(BM_DiagonalSweep)
    ->ArgsProduct({{50, 100, 200}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The once-per-solve re-layout of ĉ into blocks (parallel over a), and the per-restart set_state.
void BM_DiagonalLayout(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, state.range(1));
  Fixture f(n);
  for (auto _ : state) {
    auto layout = std::make_shared<const DiagonalCost>(f.c);
    benchmark::DoNotOptimize(layout->c.data());
  }
  state.counters["neurons/s"] =
      benchmark::Counter(static_cast<double>(f.c.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DiagonalLayout)->ArgsProduct({{100, 200}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DiagonalSetState(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  Fixture f(n);
  DiagonalNetwork net(f.w, f.c);
  for (auto _ : state) net.set_state(f.V0);
}
BENCHMARK(BM_DiagonalSetState)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ContinuousSyncStep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Fixture f(n);
  ContinuousNetwork net(f.c);
  CounterRng rng(1);
  net.initialise(-1.f, 0.01f, 0.5f, rng);
  ContinuousParams p;
  p.w = f.w;
  run_with_floor(state, f.c.size(), threads, [&] { benchmark::DoNotOptimize(continuous_sync_step(net, p)); });
}
BENCHMARK(BM_ContinuousSyncStep)
    ->ArgsProduct({{50, 100, 200}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The async continuous step (serial; a uniform random permutation per step, drawn inside the timed
// region as the solver does): u, V and ĉ are read at random.
void BM_ContinuousAsyncStep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  Fixture f(n);
  ContinuousNetwork net(f.c);
  CounterRng rng(1);
  net.initialise(-1.f, 0.01f, 0.5f, rng);
  ContinuousParams p;
  p.w = f.w;
  std::vector<uint32_t> order(f.c.size());
  std::iota(order.begin(), order.end(), 0u);
  run_with_floor(state, f.c.size(), 1, [&] {
    rng.shuffle(std::span<uint32_t>(order));
    benchmark::DoNotOptimize(continuous_async_step(net, p, order));
  });
}
BENCHMARK(BM_ContinuousAsyncStep)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

// Restarts in parallel: 8 restarts of at most 20 async sweeps each (cost order, random start) at
// n = 50; they converge in 3–5 sweeps, so the prologue (normalisation, cost order) and the balance
// of 8 unequal tasks over 2 threads decide the speed-up.
void BM_Restarts(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Fixture f(50);
  HopfieldOptions o;
  o.restarts = 8;
  o.init = HopfieldInit::kRandom;
  o.anneal_E_factor = 1.0;
  o.max_sweeps = 20;
  for (auto _ : state) benchmark::DoNotOptimize(solve_hopfield(f.inst.cost, o, 1).solution.summary.objective);
  state.counters["restarts/s"] =
      benchmark::Counter(o.restarts, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Restarts)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The default `hopfield` solver (mean-field start, then async in cost order), 8 restarts at n = 50:
// the restarts run in parallel and each one's continuous phase is itself parallel (nested).
void BM_RestartsDefault(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  Fixture f(50);
  const HopfieldOptions o;
  for (auto _ : state) benchmark::DoNotOptimize(solve_hopfield(f.inst.cost, o, 1).solution.summary.objective);
  state.counters["restarts/s"] =
      benchmark::Counter(o.restarts, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_RestartsDefault)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Marginal sums vs the naive weight matrix, same sync sweep, n = 10–15, 1 thread.
void BM_NaiveWeightsSweep(benchmark::State& state) {
  const int32_t n = static_cast<int32_t>(state.range(0));
  Fixture f(n);
  const NaiveHopfieldNetwork naive(HopfieldEnergy::kFullPlane, f.w, f.c);
  std::vector<uint8_t> V = f.V0, out(V.size());
  for (auto _ : state) {
    naive.sync_sweep(V, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["neurons/s"] =
      benchmark::Counter(static_cast<double>(V.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_NaiveWeightsSweep)->DenseRange(10, 15, 5)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MarginalSweepSmall(benchmark::State& state) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
  const int32_t n = static_cast<int32_t>(state.range(0));
  Fixture f(n);
  DiscreteNetwork net(HopfieldEnergy::kFullPlane, f.w, f.c);
  net.set_state(f.V0);
  for (auto _ : state) benchmark::DoNotOptimize(sync_sweep(net).flips);
  state.counters["neurons/s"] =
      benchmark::Counter(static_cast<double>(f.c.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_MarginalSweepSmall)->DenseRange(10, 15, 5)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  measure_copy_bandwidth();
  benchmark::AddCustomContext("copy_GBps_1thread", std::to_string(g_copy_bandwidth[1] / 1e9));
  benchmark::AddCustomContext("copy_GBps_2threads", std::to_string(g_copy_bandwidth[2] / 1e9));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
