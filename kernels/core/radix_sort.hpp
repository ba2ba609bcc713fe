// Least-significant-digit radix sort of records by an unsigned 64-bit key (Knuth, The Art of Computer
// Programming vol. 3, §5.2.5, radix sorting; Cormen et al., Introduction to Algorithms, §8.3).
//
// Algorithm: the key's significant bits B (those of the OR of all keys) are cut into ⌈B/12⌉ digits of
// equal width (at most 12 bits: at most 4 096 counters, on the stack); each digit, least significant
// first, is one stable counting sort (count, exclusive prefix sum, forward scatter into the buffer),
// so the records end in key order and equal keys keep their input order. A digit that is the same
// for every record is skipped (its counting sort would not move anything).
// Complexity: O(n·⌈B/12⌉) time, n records of the buffer (against O(n log n) comparisons for
// std::sort); B = 23 gives 2 passes, B = 64 gives 6.
// Use: kernels/statistics/scan_candidates.cpp sorts each scan's hits of the candidate index by their
// (sensor pair, track, track) key with it.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace trackassoc {

// Sorts `records` by key(record) (a uint64_t), stably. `buffer` is scratch: resized to
// records.size() when a pass runs (a caller that counts its memory reserves it first), its contents
// unspecified on return.
template <class T, class Key>
void radix_sort_by_key(std::vector<T>& records, std::vector<T>& buffer, Key key) {
  uint64_t any = 0;
  for (const T& r : records) any |= key(r);
  const int bits = std::bit_width(any);
  if (bits == 0 || records.size() < 2) return;  // every key 0, or nothing to order
  const int passes = (bits + 11) / 12, digit = (bits + passes - 1) / passes;
  const uint64_t mask = (uint64_t{1} << digit) - 1;
  std::array<std::size_t, 4096> storage;  // (each pass fills its digit's counters)
  const std::span<std::size_t> first(storage.data(), static_cast<std::size_t>(mask) + 1);
  buffer.resize(records.size());
  for (int shift = 0; shift < bits; shift += digit) {
    std::ranges::fill(first, 0);
    for (const T& r : records) ++first[(key(r) >> shift) & mask];
    if (std::ranges::find(first, records.size()) != first.end()) continue;  // one digit for all
    std::size_t sum = 0;
    for (std::size_t& f : first) sum += std::exchange(f, sum);
    for (const T& r : records) buffer[first[(key(r) >> shift) & mask]++] = r;
    records.swap(buffer);
  }
}

}  // namespace trackassoc
