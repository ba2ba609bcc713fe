// Counter-based random streams (docs/design.md §2, Determinism).
//
// Every random stream is keyed by (seed, run, stream), e.g. stream = restart number or sensor id,
// and draws number `counter` as a pure function of (key, counter): the SplitMix64 finaliser
// (Steele, Lea, Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014) applied to
// key + counter·γ. No state is shared between streams, so results are bit-identical for any thread
// count and any order in which the streams are consumed.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <utility>

namespace trackassoc {

// GCC/Clang 128-bit integer for Lemire's multiply; __extension__ keeps -Wpedantic quiet.
__extension__ using uint128 = unsigned __int128;

inline constexpr uint64_t splitmix64_mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Derives a stream key from up to four integers; distinct tuples give unrelated keys.
inline constexpr uint64_t stream_key(uint64_t seed, uint64_t a = 0, uint64_t b = 0, uint64_t c = 0) {
  uint64_t k = splitmix64_mix(seed + 0x9e3779b97f4a7c15ULL);
  k = splitmix64_mix(k ^ (a + 0x632be59bd9b4e019ULL));
  k = splitmix64_mix(k ^ (b + 0x8cb92ba72f3d8dd7ULL));
  k = splitmix64_mix(k ^ (c + 0xd1b54a32d192ed03ULL));
  return k;
}

class CounterRng {
 public:
  explicit CounterRng(uint64_t seed, uint64_t a = 0, uint64_t b = 0, uint64_t c = 0)
      : key_(stream_key(seed, a, b, c)) {}

  uint64_t next_u64() { return splitmix64_mix(key_ + (++counter_) * 0x9e3779b97f4a7c15ULL); }
  // Uniform on [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer on [0, n), unbiased (Lemire 2019, multiply-and-reject).
  uint64_t uniform_int(uint64_t n) {
    if (n <= 1) return 0;
    uint128 m = static_cast<uint128>(next_u64()) * n;
    uint64_t low = static_cast<uint64_t>(m);
    if (low < n) {
      const uint64_t threshold = (0 - n) % n;
      while (low < threshold) {
        m = static_cast<uint128>(next_u64()) * n;
        low = static_cast<uint64_t>(m);
      }
    }
    return static_cast<uint64_t>(m >> 64);
  }
  // Standard normal by Box–Muller; the second variate is kept for the next call.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * std::numbers::pi * u2);
  }
  double normal(double mean, double sigma) { return mean + sigma * normal(); }
  // Fisher–Yates shuffle. The swap partners do not depend on the array, so on large arrays they
  // are drawn kBatch at a time and prefetched before the swaps: the same draws and swaps in the
  // same order (identical result), without waiting on a cache miss per element.
  template <class T>
  void shuffle(std::span<T> v) {
    constexpr std::size_t kBatch = 16;
    std::size_t i = v.size();
    if (i * sizeof(T) > (std::size_t{1} << 18)) {
      std::size_t partner[kBatch];
      for (; i > kBatch + 1; i -= kBatch) {
        for (std::size_t t = 0; t < kBatch; ++t) {
          partner[t] = uniform_int(i - t);
          __builtin_prefetch(v.data() + partner[t], 1);
        }
        for (std::size_t t = 0; t < kBatch; ++t) std::swap(v[i - t - 1], v[partner[t]]);
      }
    }
    for (; i > 1; --i) std::swap(v[i - 1], v[uniform_int(i)]);
  }

 private:
  uint64_t key_;
  uint64_t counter_ = 0;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace trackassoc
