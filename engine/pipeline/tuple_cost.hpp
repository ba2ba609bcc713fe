// The S-D tuple cost (docs/design.md §4.3), the one rule of both S-D paths: the dense S-D tensor
// (engine/pipeline/pipeline_sd.hpp) and the default path's components
// (engine/pipeline/sparse_sd_components.hpp).
//
// A tuple with k real members (one per sensor, in sensor order) costs the sum of the link costs
// λ − G(n) of its linked pairs: every pair (all-pairs form) or consecutive members (chain form).
// It is forbidden (+inf) when
//   * two members coexist (common valid times, so the gate tested them) and fail the gate, or
//   * its members are not connected through gated-in pairs.
// A *doubtful* pair (the default path's family-wise veto, engine/pipeline/sparse_sd_pipeline.hpp:
// outside the gate, inside the gate at the tuple's family-wise level) does not forbid the tuple: it
// adds its positive link cost and links nothing (the tuple must still be connected through gated-in
// pairs). Its link entry carries the tag kDoubtfulPairTag (doubtful_pair_entry), so that it travels
// in the link matrices with the gated ones (and to other ranks with their codecs).
// A pair that never coexists carries no evidence either way (neither in the gate nor out): it
// neither forbids the tuple nor links it, so a target seen by sensor A early and sensor C late
// joins through a sensor B that saw both. A tuple of one track costs 0.
// Complexity: O(k²) link look-ups and a union-find over the k members.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/assignment/sd/assignment_sd.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

// The link entry of a doubtful pair: its (positive) link cost plus this tag; link costs are
// (λ − G(n))/f (f = 5 scans per independent scan), a doubtful pair's at most the family-wise gate's
// margin over the gate, (G_fw(n) − G(n))/f, far below it.
inline constexpr double kDoubtfulPairTag = 1e6;
inline double doubtful_pair_entry(double link_cost) { return link_cost + kDoubtfulPairTag; }
inline bool is_doubtful_pair_entry(double entry) { return entry >= kDoubtfulPairTag / 2; }

// The rule for one pair of members, the one decision both the tuple cost below and the segment
// pass's joins (engine/pipeline/track_segments.cpp) make: the pair's link cost when it is a gated-in
// pair; +inf (the pair forbids the group) when the two coexist, so the gate tested them, and it
// failed; NaN (no evidence either way) when they never coexist. `coexist()` is asked only for a
// pair that is not gated in. The never-coexisting pair is neutral by measurement (docs/design.md
// §4.3: forbidding it, as the dense S-D path once did, loses targets whose tracks start and end
// at different times).
template <class Coexist>
double sd_pair_term(const double* link, Coexist coexist) {
  if (link) return *link;
  return coexist() ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
}

// link(x, y) for members x < y: the link cost of the pair, NaN when it is not a gated-in pair;
// coexist(x, y): the two members have common valid times.
template <class Link, class Coexist>
double sd_tuple_cost(std::size_t k, bool all_pairs, Link link, Coexist coexist) {
  if (k <= 1) return 0.0;
  double cost = 0.0;
  // Connectivity through gated pairs: union-find over the k members (no cap on k: the buffer is
  // on the stack up to 32 members).
  int32_t stack_parent[32];
  std::vector<int32_t> heap_parent;
  int32_t* parent = stack_parent;
  if (k > 32) {
    heap_parent.resize(k);
    parent = heap_parent.data();
  }
  for (std::size_t x = 0; x < k; ++x) parent[x] = static_cast<int32_t>(x);
  auto root = [&](int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t groups = k;
  for (std::size_t x = 0; x < k; ++x)
    for (std::size_t y = x + 1; y < k; ++y) {
      const double gated = link(x, y);
      if (is_doubtful_pair_entry(gated)) {  // outside the gate, not vetoed (false for NaN)
        if (all_pairs || y == x + 1) cost += gated - kDoubtfulPairTag;
        continue;
      }
      const double l = sd_pair_term(std::isnan(gated) ? nullptr : &gated, [&] { return coexist(x, y); });
      if (std::isinf(l)) return l;
      if (std::isnan(l)) continue;  // never together: no evidence either way
      const int32_t rx = root(static_cast<int32_t>(x)), ry = root(static_cast<int32_t>(y));
      if (rx != ry) {
        parent[rx] = ry;
        --groups;
      }
      if (all_pairs || y == x + 1) cost += l;
    }
  return groups == 1 ? cost : std::numeric_limits<double>::infinity();
}

// The S-D tensor of this rule, written once for both S-D paths (the whole problem's tensor and each
// component's): t.n tracks per dimension, the last index of each its dummy; every entry the tuple
// cost of the members present. link(q, i, r, j), for dimensions q < r, is the link cost of track i
// of dimension q and track j of dimension r (NaN: not a gated pair); coexist(q, i, r, j) whether
// they have common valid times. Parallel over the first dimension's index (TBB) for a tensor of at
// least 2^14 entries, in one pass otherwise (a component's is mostly a few entries); the entries
// do not depend on it. O(Π(n_q + 1)·k²), k the dimensions.
template <class Link, class Coexist>
void fill_sd_tensor(CostTensorSD& t, bool all_pairs, Link link, Coexist coexist) {
  const int32_t P = t.dims();
  auto fill = [&](std::size_t b, std::size_t e) {
    std::vector<int32_t> idx(P, 0), present;
    present.reserve(P);
    for (std::size_t i0 = b; i0 < e; ++i0) {
      std::fill(idx.begin(), idx.end(), 0);
      idx[0] = static_cast<int32_t>(i0);
      const std::size_t base = i0 * t.stride[0];
      for (std::size_t r = 0; r < t.stride[0]; ++r) {
        present.clear();
        for (int32_t q = 0; q < P; ++q)
          if (idx[q] < t.n[q]) present.push_back(q);
        const double v = sd_tuple_cost(
            present.size(), all_pairs,
            [&](std::size_t x, std::size_t y) {
              return link(present[x], idx[present[x]], present[y], idx[present[y]]);
            },
            [&](std::size_t x, std::size_t y) {
              return coexist(present[x], idx[present[x]], present[y], idx[present[y]]);
            });
        t.cost[base + r] = static_cast<float>(v);  // +inf stays +inf: not allowed
        for (int32_t q = P - 1; q > 0; --q) {      // odometer over dimensions 1 … P−1
          if (++idx[q] <= t.n[q]) break;
          idx[q] = 0;
        }
      }
    }
  };
  const auto rows = static_cast<std::size_t>(t.n[0]) + 1;
  if (t.cost.size() < (std::size_t{1} << 14))
    fill(0, rows);
  else
    parallel_for_range(rows, 1, fill);
}

}  // namespace trackassoc
