// Per-scan candidate index for the calibrated gate; see kernels/statistics/scan_candidates.hpp. This
// file is the driver: the scans in blocks, each pair's hits counted over them, the count filter
// and the output; one scan's search is kernels/statistics/scan_search.hpp, the bound it tests
// kernels/statistics/scan_bound.hpp.
#include "kernels/statistics/scan_candidates.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "kernels/core/allocation_gauge.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/core/radix_sort.hpp"
#include "kernels/statistics/scan_bound.hpp"
#include "kernels/statistics/scan_search.hpp"

namespace trackassoc {
namespace {

void check_inputs(const AlignedTracks& a, const AlignedTracks& b, double cap, double scale) {
  require(a.dim == b.dim && a.dim % 2 == 0 && a.dim >= 2, "scan_candidate_pairs", "state dimensions differ");
  require(a.n_times == b.n_times, "scan_candidate_pairs", "numbers of common times differ");
  require(cap > 0.0 && std::isfinite(cap), "scan_candidate_pairs", "the cap must be finite and > 0");
  require(scale >= 1.0 && std::isfinite(scale), "scan_candidate_pairs", "radius_scale must be >= 1");
  a.check_layout("scan_candidate_pairs");
  b.check_layout("scan_candidate_pairs");
}

CandidatePairs finish(int32_t n_a, int32_t n_b, std::vector<std::pair<int32_t, int32_t>>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  CandidatePairs out;
  out.n_a = n_a;
  out.n_b = n_b;
  out.a.reserve(pairs.size());
  out.b.reserve(pairs.size());
  for (const auto& [i, j] : pairs) {
    out.a.push_back(i);
    out.b.push_back(j);
  }
  return out;
}

uint16_t saturating_sum(uint16_t x, uint16_t y) {
  return static_cast<uint16_t>(std::min<uint32_t>(uint32_t{x} + y, std::numeric_limits<uint16_t>::max()));
}

// Sorts one scan's hits in ScanHit's order (slot, a, b): by radix (kernels/core/radix_sort.hpp) on the
// key slot·2^(2w) + a·2^w + b, w the bits of the largest track index (B = 23 bits on the scale
// study's 3 × 1 000 tracks: 2 passes, where std::sort's comparisons of 12-byte hits were a fifth
// of the index's time, docs/performance.md), with `buffer` as its scratch (its contents dropped,
// its growth told to `gauge`); by std::sort below 512 hits, or when w > 24 (the key would not fit
// 64 bits).
void sort_scan_hits(std::vector<ScanHit>& hits, std::vector<ScanHit>& buffer, int track_bits,
                    AllocationGauge* gauge) {
  if (hits.size() < 512 || track_bits > 24) {
    std::sort(hits.begin(), hits.end());
    return;
  }
  buffer.clear();  // (so that a reserve copies nothing)
  gauged_reserve(buffer, hits.size(), gauge);
  const int w = track_bits;
  radix_sort_by_key(hits, buffer, [w](const ScanHit& h) {
    return (uint64_t{h.slot} << (2 * w)) | (static_cast<uint64_t>(h.a) << w) | static_cast<uint64_t>(h.b);
  });
}

// The hits gathered from a block's scans before they are sorted and merged (12 bytes each: 768 KiB).
constexpr std::size_t kPendingHits = std::size_t{1} << 16;

// Sorted hits summed in place: each pair once, its count the sum of its copies'.
void sum_copies(std::vector<ScanHit>& hits) {
  std::size_t w = 0;
  for (std::size_t r = 0; r < hits.size(); ++r) {
    if (w > 0 && hits[w - 1].same_pair(hits[r]))
      hits[w - 1].count = saturating_sum(hits[w - 1].count, hits[r].count);
    else
      hits[w++] = hits[r];
  }
  hits.resize(w);
}

// The union of two sorted, summed lists, counts of a pair in both summed.
void merge_summing(const std::vector<ScanHit>& x, const std::vector<ScanHit>& y, std::vector<ScanHit>& out) {
  auto i = x.begin(), j = y.begin();
  while (i != x.end() && j != y.end()) {
    if (*i < *j) {
      out.push_back(*i++);
    } else if (*j < *i) {
      out.push_back(*j++);
    } else {
      out.push_back(*i++);
      out.back().count = saturating_sum(out.back().count, j++->count);
    }
  }
  out.insert(out.end(), i, x.end());
  out.insert(out.end(), j, y.end());
}

// The union of the blocks' sorted, summed lists (sorted by pair, each pair once, its count the sum
// of its blocks'), merged two by two in rounds (merge_summing: O(N log B) for N hits in B blocks,
// where sorting their concatenation took O(N log N): the scale study's 11 800 hits in 2 blocks,
// 0.96 ms of the index's 12 ms of scans). Each merge's output is told to `gauge` before it is
// allocated and its inputs released after, so at most the blocks and one merge's output are held.
std::vector<ScanHit> merge_blocks(std::vector<std::vector<ScanHit>>& blocks, AllocationGauge* gauge) {
  auto release = [&](std::vector<ScanHit>& block) {
    const double freed = static_cast<double>(block.capacity() * sizeof(ScanHit));
    std::vector<ScanHit>().swap(block);
    gauge_release(gauge, freed);
  };
  while (blocks.size() > 1) {
    std::vector<std::vector<ScanHit>> merged((blocks.size() + 1) / 2);
    for (std::size_t b = 0; b + 1 < blocks.size(); b += 2) {
      gauged_reserve(merged[b / 2], blocks[b].size() + blocks[b + 1].size(), gauge);
      merge_summing(blocks[b], blocks[b + 1], merged[b / 2]);
      release(blocks[b]);
      release(blocks[b + 1]);
    }
    if (blocks.size() % 2 == 1) merged.back().swap(blocks.back());
    blocks.swap(merged);
  }
  return blocks.empty() ? std::vector<ScanHit>() : std::move(blocks.front());
}

}  // namespace

InteriorMargins interior_skip_margins(std::span<const int32_t> least_hits, int32_t n_times) {
  const auto most = static_cast<int32_t>(least_hits.size()) - 1;  // the most common scans of a pair
  // ⌈w/2⌉ odd scans at most in w consecutive ones: w = n − (margins) ≤ 2·(least[n] − 1), so a pair of
  // n common scans needs margins summing to R(n) = n − 2·least[n] + 2, ⌈R(n)/2⌉ at each end.
  auto own = [&](int32_t n) { return std::max(0, (n - 2 * least_hits[n] + 3) / 2); };
  InteriorMargins out;
  out.by_length.assign(std::max<std::size_t>(least_hits.size(), 1), 0);
  for (int32_t l = 1; l <= most; ++l) out.by_length[l] = std::max(out.by_length[l - 1], own(l));
  out.whole = n_times <= most && n_times >= 1 ? own(n_times) : 0;  // (else no two whole tracks pair)
  return out;
}

std::vector<CandidatePairs> scan_candidate_pairs(std::span<const AlignedTracks* const> sensors, double cap,
                                                 double radius_scale, AllocationGauge* gauge,
                                                 std::span<const int32_t> least_hits,
                                                 std::vector<std::size_t>* found) {
  const auto S = static_cast<int32_t>(sensors.size());
  require(S <= 256, "scan_candidate_pairs",
          "at most 256 sensors (a sensor pair is held in 16 bits), got " + std::to_string(S));
  std::vector<CandidatePairs> out(static_cast<std::size_t>(S) * S);
  for (int32_t s = 0; s < S; ++s)
    for (int32_t t = s + 1; t < S; ++t) {
      check_inputs(*sensors[s], *sensors[t], cap, radius_scale);
      out[static_cast<std::size_t>(s) * S + t].n_a = sensors[s]->n_tracks();
      out[static_cast<std::size_t>(s) * S + t].n_b = sensors[t]->n_tracks();
    }
  if (found) found->assign(out.size(), 0);
  if (S < 2) return out;
  const int32_t K = sensors[0]->n_times;
  const double c2 = cap * radius_scale * radius_scale;
  // Each scan is searched by ScanSearch (kernels/statistics/scan_search.hpp), its tracks listed
  // from the spans (valid_by_time). Scans in blocks of consecutive times (a pair found at one is
  // mostly found at the next), each block's hits deduplicated before they are kept.
  // The index of valid tracks by time (offsets and the counting pass's cursors, 2·(K + 1) int64,
  // and at most one int32 per cell of each span), counted before it is built.
  double valid_bytes = 0.0;
  for (int32_t s = 0; s < S; ++s) {
    valid_bytes += 16.0 * (static_cast<double>(K) + 1.0);
    for (int32_t i = 0; i < sensors[s]->n_tracks(); ++i) {
      const AlignedTracks::Span sp = sensors[s]->span(i);
      valid_bytes += 4.0 * std::max(0, sp.end - sp.begin);
    }
  }
  gauge_add(gauge, valid_bytes);
  std::vector<ValidByTime> valid(S);
  parallel_for_range(static_cast<std::size_t>(S), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t s = lo; s < hi; ++s) valid[s] = valid_by_time(*sensors[s]);
  });
  // Each track's invalid cells inside its span (the count filter's lower bound of a pair's common
  // valid scans) and its margin for the interior skipping (at odd scans only the pairs with a track
  // at its edge are searched, scan_candidates.hpp; a track with gaps: K, at its edge everywhere):
  // two int32 a track, counted before they are built.
  double track_bytes = 0.0;
  if (!least_hits.empty())
    for (int32_t s = 0; s < S; ++s) track_bytes += 8.0 * sensors[s]->n_tracks();
  gauge_add(gauge, track_bytes);
  const std::size_t with_filter = least_hits.empty() ? 0 : S;
  std::vector<std::vector<int32_t>> gaps(with_filter), margins(with_filter);
  bool skipping = false;  // some track has an interior
  if (!least_hits.empty()) {
    const InteriorMargins by = interior_skip_margins(least_hits, K);
    for (std::size_t s = 0; s < with_filter; ++s) {
      const AlignedTracks& x = *sensors[s];
      gaps[s].assign(x.n_tracks(), 0);
      margins[s].resize(x.n_tracks());
      for (int32_t i = 0; i < x.n_tracks(); ++i) {
        const AlignedTracks::Span sp = x.span(i);
        for (int32_t k = sp.begin; k < sp.end; ++k) gaps[s][i] += !x.valid[x.cell_base(i) + k];
        margins[s][i] = gaps[s][i] > 0 ? K : by.of(sp, K);
        skipping = skipping || 2 * margins[s][i] < sp.end - sp.begin;
      }
    }
  }
  const PartialScan partial{margins};
  // Each thread's scratch of one scan, counted before the scans for every thread.
  const double scratch_bytes = ScanSearch::scratch_bytes(sensors, valid) *
                               static_cast<double>(std::max(1, tbb::this_task_arena::max_concurrency()));
  gauge_add(gauge, scratch_bytes);
  int32_t most_tracks = 1;  // the key of sort_scan_hits: the bits of the largest track index
  for (int32_t s = 0; s < S; ++s) most_tracks = std::max(most_tracks, sensors[s]->n_tracks());
  const int track_bits = std::bit_width(static_cast<uint32_t>(most_tracks - 1));
  // Blocks of at most 8 scans, and at least as many blocks as threads while there are scans enough
  // (a file of 11 common times in blocks of 8 and 3 left one thread idle for most of the index).
  // The blocking does not change the output: each pair's count is summed over the blocks.
  const int32_t threads = std::max(1, tbb::this_task_arena::max_concurrency());
  const int32_t least_blocks = std::max({1, (K + 7) / 8, std::min(K, threads)});
  const int32_t block = std::max(1, (K + least_blocks - 1) / least_blocks);  // scans a block
  const std::size_t blocks = (static_cast<std::size_t>(K) + block - 1) / block;
  std::vector<std::vector<ScanHit>> per_block(blocks);
  parallel_for_range(blocks, 1, [&](std::size_t lo, std::size_t hi) {
    ScanSearch search;
    // The scans' hits are gathered, then sorted, summed (each pair once, its count the number of
    // scans it was found at: a pair is found at most once a scan) and merged into the block's
    // sorted set when they reach kPendingHits or the block ends: one sort of a small block's hits
    // where each scan had its own sort and merge (the scale study: 0.7 ms of its 10 ms of scans).
    // Large scans are merged one by one (a pair found at one scan is mostly found at the next:
    // kept until the block ends, the copies made a block of recorded_30k ask for 768 MiB where its
    // pairs take ~100 MiB).
    std::vector<ScanHit> scan, merged;
    for (std::size_t bl = lo; bl < hi; ++bl) {
      std::vector<ScanHit>& kept = per_block[bl];
      const auto k0 = static_cast<int32_t>(bl) * block, k1 = std::min(K, k0 + block);
      for (int32_t k = k0; k < k1; ++k) {
        search.scan(sensors, valid, k, c2, scan, gauge, skipping && k % 2 == 1 ? &partial : nullptr);
        if (scan.size() < kPendingHits && k + 1 < k1) continue;
        sort_scan_hits(scan, merged, track_bits, gauge);  // (merged is free until the merge)
        sum_copies(scan);
        gauged_reserve(merged, kept.size() + scan.size(), gauge);
        merged.clear();
        merge_summing(kept, scan, merged);
        kept.swap(merged);
        scan.clear();
      }
    }
    gauge_release(gauge, static_cast<double>((scan.capacity() + merged.capacity()) * sizeof(ScanHit)));
  });
  gauge_release(gauge, scratch_bytes);  // freed with each thread's scratch
  std::vector<ValidByTime>().swap(valid);
  gauge_release(gauge, valid_bytes);
  // By slot, then (a, b): each slot's pairs sorted, with their scans within.
  std::vector<ScanHit> all = merge_blocks(per_block, gauge);
  // The count filter (least_hits): a pair within its bound at fewer scans than the least for a
  // lower bound of its common valid scans is dropped; n ≥ |span_a ∩ span_b| − gaps_a − gaps_b, the
  // gaps being the invalid cells inside each track's span. A pair short of it at the scans searched
  // is tested at those left out (the odd ones inside both tracks' interiors), until it has the least
  // or cannot reach it: its count is then the full search's.
  const int m = sensors[0]->dim / 2;
  auto kept = [&](const ScanHit& h) {
    const int32_t s = h.slot / S, t = h.slot % S;
    const AlignedTracks &x = *sensors[s], &y = *sensors[t];
    const AlignedTracks::Span sa = x.span(h.a), sb = y.span(h.b);
    const int64_t n = static_cast<int64_t>(common_span(sa, sb).size()) - gaps[s][h.a] - gaps[t][h.b];
    const auto at =
        static_cast<std::size_t>(std::clamp<int64_t>(n, 0, static_cast<int64_t>(least_hits.size()) - 1));
    const int32_t need = std::min<int32_t>(least_hits[at], std::numeric_limits<uint16_t>::max());
    int32_t count = h.count;
    if (count >= need) return true;
    if (!skipping) return false;
    const int32_t ma = margins[s][h.a], mb = margins[t][h.b];  // (gaps: K, so lo ≥ K ≥ hi)
    const int32_t lo = std::max(sa.begin + ma, sb.begin + mb), hi = std::min(sa.end - ma, sb.end - mb);
    int32_t left = hi > lo ? hi / 2 - lo / 2 : 0;  // the odd scans in [lo, hi)
    for (int32_t k = lo | 1; k < hi && count < need && count + left >= need; k += 2, --left)
      count += within_scan_bound(x, x.cell_base(h.a) + k, y, y.cell_base(h.b) + k, m, c2);
    return count >= need;
  };
  if (found)
    for (const ScanHit& h : all) ++(*found)[h.slot];
  if (!least_hits.empty()) {  // in place: no second buffer of hits
    gauge_add(gauge, static_cast<double>(all.size()));
    std::vector<uint8_t> keep(all.size());
    parallel_for_range(all.size(), 1024, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t q = lo; q < hi; ++q) keep[q] = kept(all[q]);
    });
    std::size_t w = 0;
    for (std::size_t q = 0; q < all.size(); ++q)
      if (keep[q]) all[w++] = all[q];
    all.resize(w);
    gauge_release(gauge, static_cast<double>(keep.size()));
  }
  std::vector<std::vector<int32_t>>().swap(gaps);
  std::vector<std::vector<int32_t>>().swap(margins);
  gauge_release(gauge, track_bytes);
  // Each slot's pairs counted, then laid out (exactly their size: 8 bytes a pair) beside the hits.
  std::vector<std::size_t> per_slot(out.size(), 0);
  for (const ScanHit& h : all) ++per_slot[h.slot];
  gauge_add(gauge, static_cast<double>(all.size() * 2 * sizeof(int32_t)));
  for (std::size_t slot = 0; slot < out.size(); ++slot) {
    out[slot].a.reserve(per_slot[slot]);
    out[slot].b.reserve(per_slot[slot]);
  }
  for (const ScanHit& h : all) {
    out[h.slot].a.push_back(h.a);
    out[h.slot].b.push_back(h.b);
  }
  const double hits = static_cast<double>(all.capacity() * sizeof(ScanHit));
  std::vector<ScanHit>().swap(all);
  gauge_release(gauge, hits);
  return out;
}

CandidatePairs scan_candidate_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                    double radius_scale) {
  check_inputs(a, b, cap, radius_scale);
  const AlignedTracks* both[2] = {&a, &b};
  return std::move(scan_candidate_pairs(both, cap, radius_scale)[1]);
}

CandidatePairs scan_candidate_pairs_all_pairs(const AlignedTracks& a, const AlignedTracks& b, double cap,
                                              double radius_scale) {
  check_inputs(a, b, cap, radius_scale);
  const int m = a.dim / 2;
  const double c2 = cap * radius_scale * radius_scale;
  std::vector<std::pair<int32_t, int32_t>> all;
  for (int32_t i = 0; i < a.n_tracks(); ++i)
    for (int32_t j = 0; j < b.n_tracks(); ++j)
      for (int32_t k = 0; k < a.n_times; ++k) {  // every k, the naive peer (cell() −1 off the span)
        const int64_t ca = a.cell(i, k), cb = b.cell(j, k);
        if (ca >= 0 && cb >= 0 && a.valid[ca] && b.valid[cb] && within_scan_bound(a, ca, b, cb, m, c2)) {
          all.emplace_back(i, j);
          break;
        }
      }
  return finish(a.n_tracks(), b.n_tracks(), all);
}

}  // namespace trackassoc
