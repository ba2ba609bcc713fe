// The segment pass's graph and its rule (a) (engine/pipeline/track_segments.hpp): the problem's
// local tracks as nodes, with their report intervals, coasted tails, latest reports and gated-in
// links, and the overlap rule by which two tracks of one sensor follow each other (the plain
// overlap, the earlier track's coasted tail, the takeover of a lost track, a duplicate on a listed
// sensor). Internal to engine/pipeline/track_segments.cpp.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/pipeline/coasted_tail.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/track_segments.hpp"
#include "engine/pipeline/tuple_cost.hpp"
#include "io/track_file.hpp"

namespace trackassoc::segments {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The problem's nodes with their report intervals, links and targets.
struct SegmentGraph {
  const SparseSDProblem& p;
  std::vector<double> first, last;               // report interval per node
  std::vector<std::size_t> first_row, last_row;  // their rows in the track table
  // Per node, the last report before its coasted tail (SegmentOptions::coast_growth; the last
  // report when there is none): its time and row.
  std::vector<double> held_last;
  std::vector<std::size_t> held_row;
  // Per node, its latest reports (the takeover's lost-track test; empty without the coast rule).
  std::vector<LatestReports> latest;
  std::vector<std::vector<std::pair<int32_t, double>>> links;  // gated-in neighbours, link cost
  // (min node, max node) → link cost; a doubtful pair's as its tagged entry (doubtful_pair_entry,
  // engine/pipeline/tuple_cost.hpp), as the components' link matrices hold it.
  std::unordered_map<uint64_t, double> link_of;

  static uint64_t key(int32_t u, int32_t v) {
    if (u > v) std::swap(u, v);
    return (static_cast<uint64_t>(static_cast<uint32_t>(u)) << 32) | static_cast<uint32_t>(v);
  }
  double overlap_s(int32_t u, int32_t v) const {
    return std::min(last[u], last[v]) - std::max(first[u], first[v]);
  }
  // The overlap of rule (a): as overlap_s of `early` (the one that starts first) and `late`, early's
  // coasted tail left out. Only the earlier one's: a later track that is all tail (one update, then
  // predictions) would otherwise follow any track it starts beside, however long that one goes on
  // updating after it (on widearea, 6 false tuples).
  double held_overlap_s(int32_t early, int32_t late) const {
    return std::min(held_last[early], last[late]) - first[late];
  }
  // The pair's term in a join, as a tuple reads it (engine/pipeline/tuple_cost.hpp): a gated pair's
  // link cost; a doubtful pair's positive link cost (*doubtful set, when given: no evidence); +inf
  // when the two coexist otherwise (tested, outside the gate); NaN when they never coexist.
  double term(int32_t u, int32_t v, bool* doubtful = nullptr) const {
    auto it = link_of.find(key(u, v));
    const bool tagged = it != link_of.end() && is_doubtful_pair_entry(it->second);
    if (doubtful) *doubtful = tagged;
    if (tagged) return it->second - kDoubtfulPairTag;
    return sd_pair_term(it == link_of.end() ? nullptr : &it->second, [&] { return p.coexist(u, v); });
  }
  int32_t node(int32_t s, int32_t track) const {  // −1 when sensor s has no such track
    const std::vector<int32_t>& t = p.aligned[s].track;
    auto it = std::lower_bound(t.begin(), t.end(), track);
    return it != t.end() && *it == track ? p.offset[s] + static_cast<int32_t>(it - t.begin()) : -1;
  }
};

SegmentGraph build_graph(const SparseSDProblem& p, const TrackTable& tracks, double coast_growth);

// The continuation test (d) of engine/pipeline/track_hygiene.hpp: its manoeuvre allowance q = σ_a²
// and gate.
struct MergeGate {
  double q = 0.0, threshold = 0.0;
};

// Rule (a) of the header, per sensor of the problem, for a join or a merge.
enum class Sequence { kJoin, kMerge };
struct OverlapRule {
  const TrackTable* tracks = nullptr;
  MergeGate continuation;
  double max_overlap_s = 0.0;
  double takeover_s = 0.0;
  double coast_growth = 0.0;
  std::vector<uint8_t> duplicates;  // per problem sensor: its tracks may be duplicates
  double duplicate_threshold = 0.0;
  int32_t min_duplicate_times = 1;
  // u and m follow each other: they overlap by at most max_overlap_s, or, in a join, do so once
  // the earlier one's coasted tail is left out and the later one's first report continues the
  // earlier one's last report before its tail (the continuation test): a tracker's successor of the track it
  // lost. Or the later one takes over from a lost track (takeover_s), in a join or a merge.
  bool follows(const SegmentGraph& g, int32_t u, int32_t m, Sequence kind = Sequence::kJoin) const {
    if (g.overlap_s(u, m) <= max_overlap_s) return true;
    const bool u_first = g.first[u] <= g.first[m];
    const int32_t early = u_first ? u : m, late = u_first ? m : u;
    if (kind == Sequence::kJoin && g.first[early] < g.first[late] &&
        g.held_overlap_s(early, late) <= max_overlap_s)
      return continues(g.held_row[early], g.first_row[late]);
    return takes_over(g, early, late);
  }
  // The continuation test from report `from` of the earlier track to the later one's first report.
  bool continues(std::size_t from, std::size_t first_of_later) const {
    return continuation_statistic(*tracks, from, first_of_later, continuation.q) <= continuation.threshold;
  }
  bool takes_over(const SegmentGraph& g, int32_t early, int32_t late) const {
    if (!(g.overlap_s(early, late) <= takeover_s) || g.latest.empty() || !(g.first[early] < g.first[late]) ||
        !(g.last[early] < g.last[late]))
      return false;
    const LatestReports& r = g.latest[static_cast<std::size_t>(early)];
    if (!r.lost_after(g.first[late], coast_growth)) return false;
    return continues(r.row[r.last_at_or_before(g.first[late] + max_overlap_s)], g.first_row[late]);
  }
  // Free node u may join beside node m, both of problem sensor s: they follow each other, or u is
  // a duplicate of m on a listed sensor.
  bool allows(const SegmentGraph& g, int32_t u, int32_t m, int32_t s, Sequence kind = Sequence::kJoin) const {
    if (follows(g, u, m, kind)) return true;
    if (!duplicates[s]) return false;
    const int32_t o = g.p.offset[s];
    const DuplicateStatistic d = duplicate_statistic(
        g.p.aligned[s], u - o, m - o, std::max(g.first[u], g.first[m]), std::min(g.last[u], g.last[m]));
    return d.times >= min_duplicate_times && d.max_d2 <= duplicate_threshold;
  }
};

OverlapRule make_overlap_rule(const SparseSDProblem& p, const SegmentOptions& o, const TrackTable& tracks,
                              const MergeGate& continuation);

}  // namespace trackassoc::segments
