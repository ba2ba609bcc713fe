// The counter-based random streams (kernels/core/random.hpp) and the stream independence that
// determinism rests on (docs/design.md §2): distinct keys (seed, run, restart, stream) give distinct,
// uncorrelated sequences; one key gives one sequence whatever the thread count and the order in
// which streams are created or consumed; no two streams of the simulation (engine/
// simulation_truth.hpp SimulationStream) collide. And the batched Fisher–Yates shuffle of large
// arrays equals the textbook one-swap-at-a-time loop, draw for draw.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <thread>
#include <unordered_set>
#include <vector>

#include "engine/simulation/simulation_truth.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {
namespace {

template <class T>
void textbook_shuffle(CounterRng& rng, std::vector<T>& v) {
  for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[rng.uniform_int(i)]);
}

TEST(CounterRng, BatchedShuffleEqualsTextbookFisherYates) {
  // Around the batching threshold (256 KiB) and with every remainder of the 16-draw batches.
  for (std::size_t n : {0u, 1u, 2u, 17u, 1000u, 65536u, 65537u, 65553u, 70000u, 100003u}) {
    std::vector<uint32_t> a(n), b(n);
    std::iota(a.begin(), a.end(), 0u);
    b = a;
    CounterRng ra(77, n), rb(77, n);
    ra.shuffle(std::span<uint32_t>(a));
    textbook_shuffle(rb, b);
    ASSERT_EQ(a, b) << "n = " << n;
    EXPECT_EQ(ra.next_u64(), rb.next_u64()) << "the streams must stay in step, n = " << n;
    std::vector<uint32_t> sorted = a;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(sorted[k], k);
  }
  // An 8-byte element type crosses the threshold at half the count.
  std::vector<uint64_t> a(40000), b;
  std::iota(a.begin(), a.end(), uint64_t{5});
  b = a;
  CounterRng ra(3), rb(3);
  ra.shuffle(std::span<uint64_t>(a));
  textbook_shuffle(rb, b);
  EXPECT_EQ(a, b);
}

using Key = std::array<uint64_t, 4>;  // (seed, run, restart, stream)

std::vector<double> uniforms(const Key& k, std::size_t n) {
  CounterRng rng(k[0], k[1], k[2], k[3]);
  std::vector<double> u(n);
  for (auto& x : u) x = rng.uniform();
  return u;
}

// Pearson correlation of two equally long samples.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  const double ma = std::accumulate(a.begin(), a.end(), 0.0) / n,
               mb = std::accumulate(b.begin(), b.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

TEST(CounterRng, NeighbouringKeysGiveUncorrelatedSequences) {
  // Keys one apart in each component, and with two components swapped (the key is a chain of
  // mixes, so (a, b) and (b, a) must differ too). For independent uniforms the correlation of
  // n pairs has standard deviation 1/sqrt(n): 5/sqrt(n) is a 5-sigma bound.
  const std::size_t n = 100000;
  const double bound = 5.0 / std::sqrt(double(n));
  const Key base{7, 3, 2, 5};
  std::vector<Key> others;
  for (int c = 0; c < 4; ++c) {
    Key k = base;
    ++k[c];
    others.push_back(k);
  }
  others.push_back({7, 2, 3, 5});
  others.push_back({7, 3, 5, 2});
  others.push_back({3, 7, 2, 5});
  others.push_back({0, 0, 0, 0});
  const std::vector<double> a = uniforms(base, n);
  const double mean = std::accumulate(a.begin(), a.end(), 0.0) / double(n);
  EXPECT_NEAR(mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / double(n)));  // U(0,1): σ² = 1/12
  for (const Key& k : others) {
    const std::vector<double> b = uniforms(k, n);
    EXPECT_LT(std::abs(correlation(a, b)), bound) << k[0] << " " << k[1] << " " << k[2] << " " << k[3];
    EXPECT_NE(a, b);
    // Nor is one stream the other shifted by a few draws (keys a multiple of γ apart would be).
    for (std::size_t lag = 1; lag <= 3; ++lag)
      EXPECT_LT(std::abs(correlation(std::vector<double>(a.begin() + lag, a.end()),
                                     std::vector<double>(b.begin(), b.end() - lag))),
                bound);
  }
  // Within one stream, successive draws are uncorrelated as well.
  EXPECT_LT(std::abs(correlation(std::vector<double>(a.begin() + 1, a.end()),
                                 std::vector<double>(a.begin(), a.end() - 1))),
            bound);
}

TEST(CounterRng, OneKeyOneSequenceWhateverTheThreadsAndTheOrder) {
  // 64 streams of 1000 draws: drawn in order on one thread, then by 2, 3 and 8 threads each
  // taking every T-th stream in reverse, then all 64 interleaved draw by draw.
  const std::size_t streams = 64, draws = 1000;
  auto key = [](std::size_t s) { return Key{11, s % 4, s / 4, s % 3}; };
  std::vector<std::vector<uint64_t>> serial(streams, std::vector<uint64_t>(draws));
  for (std::size_t s = 0; s < streams; ++s) {
    const Key k = key(s);
    CounterRng rng(k[0], k[1], k[2], k[3]);
    for (auto& x : serial[s]) x = rng.next_u64();
  }
  for (std::size_t threads : {2u, 3u, 8u}) {
    std::vector<std::vector<uint64_t>> got(streams, std::vector<uint64_t>(draws));
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        for (std::size_t s = streams; s-- > 0;)
          if (s % threads == t) {
            const Key k = key(s);
            CounterRng rng(k[0], k[1], k[2], k[3]);
            for (auto& x : got[s]) x = rng.next_u64();
          }
      });
    for (auto& th : pool) th.join();
    EXPECT_EQ(got, serial) << threads << " threads";
  }
  std::vector<CounterRng> rngs;
  for (std::size_t s = streams; s-- > 0;) {
    const Key k = key(s);
    rngs.emplace_back(k[0], k[1], k[2], k[3]);  // created in reverse order
  }
  for (std::size_t d = 0; d < draws; ++d)
    for (std::size_t s = 0; s < streams; ++s) ASSERT_EQ(rngs[streams - 1 - s].next_u64(), serial[s][d]);
}

TEST(CounterRng, NoTwoSimulationStreamsCollide) {
  // Every stream the simulation can key, CounterRng(seed, run, stream_id(tag, index), sub), for
  // seeds 0..49, runs 0..3, every SimulationStream tag, indices 0..7 (sensors, targets) and subs
  // 0..1: the first 8 draws of all 38 400 of them are 307 200 distinct 64-bit values. A repeated value
  // would mean two streams that share (or overlap in) their sequences.
  const std::vector<SimulationStream> tags{
      SimulationStream::kTargetManoeuvre,   SimulationStream::kRandomTarget,
      SimulationStream::kDetection,         SimulationStream::kClutter,
      SimulationStream::kShuffle,           SimulationStream::kRandomManoeuvre,
      SimulationStream::kRecordingWindow,   SimulationStream::kPhantomCount,
      SimulationStream::kPhantomTrajectory, SimulationStream::kPhantomManoeuvre,
      SimulationStream::kPhantomWindow,     SimulationStream::kPhantomDetection};
  std::unordered_set<uint64_t> seen;
  std::size_t drawn = 0;
  for (uint64_t seed = 0; seed < 50; ++seed)
    for (uint64_t run = 0; run < 4; ++run)
      for (SimulationStream tag : tags)
        for (uint64_t index = 0; index < 8; ++index)
          for (uint64_t sub = 0; sub < 2; ++sub) {
            CounterRng rng(seed, run, stream_id(tag, index), sub);
            for (int d = 0; d < 8; ++d, ++drawn)
              ASSERT_TRUE(seen.insert(rng.next_u64()).second)
                  << "seed " << seed << " run " << run << " tag " << static_cast<uint64_t>(tag) << " index "
                  << index << " sub " << sub << " draw " << d;
          }
  EXPECT_EQ(drawn, 307200u);
}

}  // namespace
}  // namespace trackassoc
