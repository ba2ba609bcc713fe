// kernels/core/radix_sort.hpp against std::stable_sort: keys of 0 to 64 significant bits (0 to 6
// passes, odd and even, skipped digits), sizes around the edges, many equal keys (stability), and
// parallel chunks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/core/radix_sort.hpp"
#include "kernels/core/random.hpp"

namespace trackassoc {
namespace {

struct Record {
  uint64_t key = 0;
  int32_t input = 0;  // position in the input: equal keys must keep its order
};

std::vector<Record> random_records(std::size_t n, int key_bits, uint64_t distinct, uint64_t seed) {
  CounterRng rng(seed, 0, 0);
  const uint64_t mask = key_bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << key_bits) - 1;
  std::vector<uint64_t> pool(distinct);
  for (uint64_t& k : pool) k = rng.next_u64() & mask;
  std::vector<Record> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = {pool[rng.uniform_int(distinct)], static_cast<int32_t>(i)};
  return r;
}

void expect_sorted_as_stable_sort(std::vector<Record> records, std::size_t chunks = 1) {
  std::vector<Record> expected = records, buffer(7);  // (a buffer that starts with other contents)
  std::stable_sort(expected.begin(), expected.end(),
                   [](const Record& x, const Record& y) { return x.key < y.key; });
  radix_sort_by_key(
      records, buffer, [](const Record& r) { return r.key; }, chunks);
  ASSERT_EQ(records.size(), expected.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    ASSERT_EQ(records[i].key, expected[i].key) << "at " << i;
    ASSERT_EQ(records[i].input, expected[i].input) << "at " << i << ": equal keys out of input order";
  }
}

TEST(RadixSort, EqualsStableSortForEveryKeyWidth) {
  // 1 (≤ 12 bits), 2, 3 (odd: the result in the buffer's storage), 4, 5 and 6 passes (64 bits).
  for (const int bits : {1, 5, 12, 13, 23, 25, 36, 37, 48, 50, 63, 64})
    for (const std::size_t n : {std::size_t{2}, std::size_t{3}, std::size_t{511}, std::size_t{4096}}) {
      SCOPED_TRACE("bits " + std::to_string(bits) + ", n " + std::to_string(n));
      expect_sorted_as_stable_sort(random_records(n, bits, n, 100 + static_cast<uint64_t>(bits)));
    }
}

TEST(RadixSort, KeepsTheInputOrderOfEqualKeys) {
  expect_sorted_as_stable_sort(random_records(5000, 40, 3, 7));  // three keys, 5 000 records
  expect_sorted_as_stable_sort(random_records(1000, 64, 1, 8));  // one key: every pass skipped
}

// Parallel chunks (counted and scattered apart, offsets in (digit, chunk) order): the one-chunk
// order, stable, for chunk counts that do not divide the records and more chunks than records.
TEST(RadixSort, ChunksGiveTheOneChunkOrder) {
  for (const std::size_t chunks : {std::size_t{2}, std::size_t{3}, std::size_t{16}}) {
    SCOPED_TRACE("chunks " + std::to_string(chunks));
    expect_sorted_as_stable_sort(random_records(50001, 32, 20000, 11), chunks);
    expect_sorted_as_stable_sort(random_records(50001, 64, 7, 12), chunks);  // equal keys across chunks
    expect_sorted_as_stable_sort(random_records(5, 20, 5, 13), chunks);
  }
}

TEST(RadixSort, ZeroKeysEmptyAndOneRecordAreLeftAsTheyAre) {
  std::vector<Record> zeros{{0, 0}, {0, 1}, {0, 2}}, none, one{{42, 0}}, buffer;
  radix_sort_by_key(zeros, buffer, [](const Record& r) { return r.key; });
  EXPECT_EQ(zeros[0].input + zeros[1].input * 10 + zeros[2].input * 100, 210);
  radix_sort_by_key(none, buffer, [](const Record& r) { return r.key; });
  EXPECT_TRUE(none.empty());
  radix_sort_by_key(one, buffer, [](const Record& r) { return r.key; });
  EXPECT_EQ(one[0].key, 42u);
}

TEST(RadixSort, SortsDescendingInput) {
  std::vector<Record> r(3000);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = {(r.size() - i) * 1000003u, static_cast<int32_t>(i)};
  expect_sorted_as_stable_sort(r);
}

}  // namespace
}  // namespace trackassoc
