// Candidate pairs as a sorted list of (a, b), for comparing an index's output with an expectation
// (tests/kernels/statistics/test_scan_candidates_*.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc::testing_support {

inline std::vector<std::pair<int32_t, int32_t>> pairs_of(const CandidatePairs& c) {
  std::vector<std::pair<int32_t, int32_t>> out;
  for (std::size_t q = 0; q < c.size(); ++q) out.emplace_back(c.a[q], c.b[q]);
  return out;
}

}  // namespace trackassoc::testing_support
