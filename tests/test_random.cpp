// The counter-based random streams (kernels/random.hpp): the batched Fisher–Yates shuffle of large
// arrays equals the textbook one-swap-at-a-time loop, draw for draw.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "kernels/random.hpp"

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

}  // namespace
}  // namespace trackassoc
