// Least-significant-digit radix sort of records by an unsigned 64-bit key (Knuth, The Art of Computer
// Programming vol. 3, §5.2.5, radix sorting; Cormen et al., Introduction to Algorithms, §8.3).
//
// Algorithm: the key's significant bits B (those of the OR of all keys) are cut into ⌈B/12⌉ digits of
// equal width (at most 12 bits: at most 4 096 counters a chunk); each digit, least significant
// first, is one stable counting sort (count, exclusive prefix sum, forward scatter into the buffer),
// so the records end in key order and equal keys keep their input order. A digit that is the same
// for every record is skipped (its counting sort would not move anything). With chunks > 1 the
// records are cut into that many consecutive ranges, each counted and scattered by its own task
// (TBB, kernels/core/parallel.hpp) with its own counters, the offsets laid out in (digit, chunk)
// order: the result is the one-chunk result, whatever the number of chunks or threads.
// Complexity: O(n·⌈B/12⌉) time (against O(n log n) comparisons for std::sort), a buffer of n
// records and chunks·2^digit counters (one chunk's on the stack); B = 23 gives 2 passes, B = 32 gives 3, B =
// 64 gives 6. Uses: kernels/statistics/scan_candidates.cpp (each scan's hits of the candidate index, by their
// (sensor pair, track, track) key); kernels/hopfield/hopfield.cpp (the cost order of a tensor's
// entries, by the float costs' bit patterns, in parallel chunks).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/core/parallel.hpp"

namespace trackassoc {

// Sorts `records` by key(record) (a uint64_t), stably. `buffer` is scratch: resized to
// records.size() when a pass runs (a caller that counts its memory reserves it first), its contents
// unspecified on return. chunks ≥ 1 (clamped to the number of records): the parallel ranges above.
template <class T, class Key>
void radix_sort_by_key(std::vector<T>& records, std::vector<T>& buffer, Key key, std::size_t chunks = 1) {
  const std::size_t n = records.size();
  if (n < 2) return;  // nothing to order
  chunks = std::clamp<std::size_t>(chunks, 1, n);
  const std::size_t chunk = (n + chunks - 1) / chunks;
  auto each_chunk = [&](auto&& fn) {  // fn(chunk index, first record, end)
    parallel_for_range(chunks, 1, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) fn(t, t * chunk, std::min(n, (t + 1) * chunk));
    });
  };
  uint64_t all = 0;
  if (chunks == 1) {
    for (const T& r : records) all |= key(r);
  } else {
    std::vector<uint64_t> any(chunks, 0);
    each_chunk([&](std::size_t t, std::size_t a, std::size_t e) {
      for (; a < e; ++a) any[t] |= key(records[a]);
    });
    for (const uint64_t x : any) all |= x;
  }
  const int bits = std::bit_width(all);
  if (bits == 0) return;  // every key 0
  const int passes = (bits + 11) / 12, digit = (bits + passes - 1) / passes;
  const uint64_t mask = (uint64_t{1} << digit) - 1;
  const auto digits = static_cast<std::size_t>(mask) + 1;
  // count[chunk·digits + digit], then its offsets; one chunk's on the stack (no allocation a call)
  std::array<std::size_t, 4096> one_chunk;
  std::vector<std::size_t> many_chunks(chunks > 1 ? chunks * digits : 0);
  std::size_t* const count = chunks > 1 ? many_chunks.data() : one_chunk.data();
  buffer.resize(n);
  for (int shift = 0; shift < bits; shift += digit) {
    each_chunk([&](std::size_t t, std::size_t a, std::size_t e) {
      std::size_t* c = count + t * digits;
      std::fill(c, c + digits, 0);
      for (; a < e; ++a) ++c[(key(records[a]) >> shift) & mask];
    });
    std::size_t sum = 0, largest = 0;
    for (std::size_t d = 0; d < digits; ++d) {
      std::size_t total = 0;
      for (std::size_t t = 0; t < chunks; ++t) {
        const std::size_t c = count[t * digits + d];
        count[t * digits + d] = sum;
        sum += c;
        total += c;
      }
      largest = std::max(largest, total);
    }
    if (largest == n) continue;  // one digit for all
    each_chunk([&](std::size_t t, std::size_t a, std::size_t e) {
      std::size_t* offset = count + t * digits;
      for (; a < e; ++a) buffer[offset[(key(records[a]) >> shift) & mask]++] = records[a];
    });
    records.swap(buffer);
  }
}

}  // namespace trackassoc
