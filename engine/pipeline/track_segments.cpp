// Track segments joined to their targets (see track_segments.hpp).
#include "engine/pipeline/track_segments.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "engine/pipeline/segment_graph.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/pipeline/tuple_cost.hpp"
#include "io/memory_budget.hpp"
#include "kernels/assignment/clusters.hpp"
#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

void SegmentOptions::validate() const {
  require(std::isfinite(max_overlap_s) && max_overlap_s >= 0.0, "segments.max_overlap_s",
          "expected a finite value >= 0 [s]");
  require(duplicate_probability > 0.0 && duplicate_probability < 1.0, "segments.duplicate_probability",
          "expected a probability in (0, 1)");
  require(min_duplicate_times >= 1, "segments.min_duplicate_times", "expected at least 1");
  require(std::isfinite(coast_growth) && coast_growth >= 0.0, "segments.coast_growth",
          "expected a finite value >= 0");
  require(std::isfinite(successor_manoeuvre_sigma) && successor_manoeuvre_sigma >= 0.0,
          "segments.successor_manoeuvre_sigma", "expected a finite value >= 0 [m/s^2]");
  require(std::isfinite(takeover_s) && takeover_s >= 0.0, "segments.takeover_s",
          "expected a finite value >= 0 [s]");
}

nlohmann::json SegmentOptions::to_json() const {
  return {{"enabled", enabled},
          {"max_overlap_s", max_overlap_s},
          {"duplicate_sensors", duplicate_sensors},
          {"duplicate_probability", duplicate_probability},
          {"min_duplicate_times", min_duplicate_times},
          {"coast_growth", coast_growth},
          {"successor_manoeuvre_sigma", successor_manoeuvre_sigma},
          {"takeover_s", takeover_s}};
}

void check_duplicate_sensors(const SegmentOptions& options, const std::vector<int32_t>& sensor_ids) {
  for (const int32_t id : options.duplicate_sensors)
    require(std::find(sensor_ids.begin(), sensor_ids.end(), id) != sensor_ids.end(),
            "segments.duplicate_sensors",
            "sensor " + std::to_string(id) + " is not one of the associated sensors");
}

namespace {

using segments::build_graph;
using segments::kInf;
using segments::make_overlap_rule;
using segments::MergeGate;
using segments::OverlapRule;
using segments::SegmentGraph;
using segments::Sequence;

struct Target {
  std::vector<std::vector<int32_t>> members;  // per sensor, nodes in the order they joined
  std::size_t tuple = 0;                      // its row in the assignment
  bool grew = false;
};

// Cost of joining free node u (sensor s) to target t, +inf when (a), (b) or (c) fails.
double join_cost(const SegmentGraph& g, const Target& t, int32_t u, int32_t s, const OverlapRule& rule) {
  for (int32_t m : t.members[s])
    if (!rule.allows(g, u, m, s)) return kInf;  // (a)
  double cost = 0.0;
  bool evidence = false;
  for (std::size_t r = 0; r < t.members.size(); ++r) {
    if (static_cast<int32_t>(r) == s) continue;
    for (int32_t m : t.members[r]) {
      bool doubtful = false;
      const double c = g.term(u, m, &doubtful);
      if (std::isinf(c)) return kInf;  // (c): tested, outside the gate
      if (std::isnan(c)) continue;     // never together
      cost += c;
      evidence |= !doubtful && g.overlap_s(u, m) > 0.0;  // (b)
    }
  }
  return evidence ? cost : kInf;
}

// One round: the LAP per connected component of the candidate graph; returns the joins made and
// adds those that joined as duplicates (a) to *duplicates.
int32_t join_round(const SegmentGraph& g, std::vector<Target>& targets, std::vector<int32_t>& target_of,
                   const OverlapRule& rule, int32_t* duplicates) {
  const SparseSDProblem& p = g.p;
  struct Candidate {
    int32_t u, t;
    double cost;
  };
  std::vector<Candidate> cand;
  for (int32_t u = 0; u < p.nodes(); ++u) {
    if (target_of[u] >= 0) continue;
    std::vector<int32_t> seen;
    for (const auto& [v, c] : g.links[u]) {
      const int32_t t = target_of[v];
      if (t < 0 || std::find(seen.begin(), seen.end(), t) != seen.end()) continue;
      seen.push_back(t);
      const double cost = join_cost(g, targets[t], u, p.sensor_of(u), rule);
      if (std::isfinite(cost)) cand.push_back({u, t, cost});
    }
  }
  if (cand.empty()) return 0;
  // Components over free nodes (0..N−1) and targets (N..N+T−1).
  const int32_t N = p.nodes();
  std::vector<int32_t> eu, ev;
  for (const Candidate& c : cand) eu.push_back(c.u), ev.push_back(N + c.t);
  const Components comp = connected_components(N + static_cast<int32_t>(targets.size()), eu, ev);
  std::vector<std::vector<std::size_t>> by_comp(comp.count);
  for (std::size_t q = 0; q < cand.size(); ++q) by_comp[comp.label[cand[q].u]].push_back(q);
  std::vector<std::pair<int32_t, int32_t>> joins;  // (u, t)
  for (const auto& qs : by_comp) {
    if (qs.empty()) continue;
    std::vector<int32_t> rows, cols;
    for (std::size_t q : qs) rows.push_back(cand[q].u), cols.push_back(cand[q].t);
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    std::sort(cols.begin(), cols.end());
    cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    const int32_t R = static_cast<int32_t>(rows.size()), C = static_cast<int32_t>(cols.size());
    std::vector<double> cost(static_cast<std::size_t>(R) * C, kInf);
    for (std::size_t q : qs) {
      const int32_t i =
          static_cast<int32_t>(std::lower_bound(rows.begin(), rows.end(), cand[q].u) - rows.begin());
      const int32_t j =
          static_cast<int32_t>(std::lower_bound(cols.begin(), cols.end(), cand[q].t) - cols.begin());
      cost[static_cast<std::size_t>(i) * C + j] = cand[q].cost;
    }
    LapOptions lap;
    lap.allow_unassigned = true;
    lap.unassigned_cost = 0.0;  // link costs are ≤ 0: every allowed join is worth making
    const LapResult res = solve_lap(cost, R, C, lap);
    for (int32_t i = 0; i < R; ++i) {
      const int32_t j = res.row_to_col[i];
      if (j >= 0 && std::isfinite(cost[static_cast<std::size_t>(i) * C + j]))
        joins.push_back({rows[i], cols[j]});
    }
  }
  for (const auto& [u, t] : joins) {
    std::vector<int32_t>& same = targets[t].members[p.sensor_of(u)];
    *duplicates += std::any_of(same.begin(), same.end(), [&](int32_t m) { return !rule.follows(g, u, m); });
    same.push_back(u);
    targets[t].grew = true;
    target_of[u] = t;
  }
  return static_cast<int32_t>(joins.size());
}

// Cost of merging targets a and b into one (the merge rule of the header: (a) the plain overlap or
// a takeover, (d) each member from its predecessor, (b) one link over common reports, (c) no failed
// gate), +inf when a rule fails. Both sensors break at once (both keys of a swap cut), or one after
// the other (a radar network's handover, a fade on one radar, then on another): then only the
// members that report while the other target's do are linked, A₂ with B₁ of {A₁, B₁} and {A₂, B₂},
// so (b) asks for one such link, not one per member (which merged no staggered break; the figures
// are in docs/design.md §4.10, "Staggered breaks").
double merge_cost(const SegmentGraph& g, const TrackTable& tracks, const Target& a, const Target& b,
                  const OverlapRule& rule, const MergeGate& gate) {
  const std::size_t S = a.members.size();
  for (std::size_t s = 0; s < S; ++s)
    for (int32_t u : a.members[s])
      for (int32_t m : b.members[s])
        if (!rule.allows(g, u, m, static_cast<int32_t>(s), Sequence::kMerge)) return kInf;  // (a)
  bool continued = false;                                                                   // (d)
  for (std::size_t s = 0; s < S; ++s)
    for (const auto& [x, y] : predecessors_across(a.members[s], b.members[s], g.first, g.last)) {
      const bool takeover = g.overlap_s(x, y) > rule.max_overlap_s && rule.takes_over(g, x, y);
      if (!takeover && continuation_statistic(tracks, g.last_row[x], g.first_row[y], gate.q) > gate.threshold)
        return kInf;
      continued = true;
    }
  if (!continued) return kInf;  // (d)
  double cost = 0.0;
  bool evidence = false;  // (b)
  for (std::size_t s = 0; s < S; ++s)
    for (int32_t u : a.members[s])
      for (std::size_t r = 0; r < S; ++r) {
        if (r == s) continue;
        for (int32_t m : b.members[r]) {
          bool doubtful = false;
          const double c = g.term(u, m, &doubtful);
          if (std::isinf(c)) return kInf;  // (c)
          if (std::isnan(c)) continue;
          cost += c;
          evidence = evidence || (!doubtful && g.overlap_s(u, m) > 0.0);
        }
      }
  return evidence ? cost : kInf;  // (b)
}

// One round of merges: every pair of targets linked by a gated-in pair of members is a candidate;
// the cheapest are taken first, each target in at most one merge per round (the merged target's
// tuple is the earlier one's; the other's is dropped). Returns the merges made.
int32_t merge_round(const SegmentGraph& g, const TrackTable& tracks, std::vector<Target>& targets,
                    std::vector<int32_t>& target_of, std::vector<uint8_t>& dissolved, const OverlapRule& rule,
                    const MergeGate& gate) {
  struct Candidate {
    double cost;
    int32_t a, b;
  };
  std::vector<Candidate> cand;
  for (int32_t a = 0; a < static_cast<int32_t>(targets.size()); ++a) {
    if (dissolved[a]) continue;
    std::vector<int32_t> seen;
    for (const auto& m : targets[a].members)
      for (int32_t u : m)
        for (const auto& [v, c] : g.links[u]) {
          const int32_t b = target_of[v];
          if (b <= a || dissolved[b] || std::find(seen.begin(), seen.end(), b) != seen.end()) continue;
          seen.push_back(b);
          const double cost = merge_cost(g, tracks, targets[a], targets[b], rule, gate);
          if (std::isfinite(cost)) cand.push_back({cost, a, b});
        }
  }
  std::stable_sort(cand.begin(), cand.end(),
                   [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
  std::vector<uint8_t> used(targets.size(), 0);
  int32_t merges = 0;
  for (const Candidate& c : cand) {
    if (used[c.a] || used[c.b]) continue;
    used[c.a] = used[c.b] = 1;
    Target& keep = targets[c.a];
    for (std::size_t s = 0; s < keep.members.size(); ++s)
      for (int32_t u : targets[c.b].members[s]) {
        keep.members[s].push_back(u);
        target_of[u] = c.a;
      }
    keep.grew = true;
    dissolved[c.b] = 1;
    ++merges;
  }
  return merges;
}

// The tuple cost of a set of nodes: Σ of the link costs of its linked and doubtful pairs.
double tuple_cost(const SegmentGraph& g, const std::vector<int32_t>& nodes) {
  double c = 0.0;
  for (std::size_t a = 0; a < nodes.size(); ++a)
    for (std::size_t b = a + 1; b < nodes.size(); ++b)
      if (const double term = g.term(nodes[a], nodes[b]); std::isfinite(term)) c += term;
  return c;
}

}  // namespace

std::vector<std::pair<int32_t, int32_t>> predecessors_across(std::span<const int32_t> a,
                                                             std::span<const int32_t> b,
                                                             std::span<const double> first,
                                                             std::span<const double> last) {
  std::vector<std::pair<int32_t, bool>> members;  // (node, of b)
  for (int32_t u : a) members.push_back({u, false});
  for (int32_t u : b) members.push_back({u, true});
  const auto before = [&](int32_t x, int32_t y) { return std::pair(first[x], x) < std::pair(first[y], y); };
  std::vector<std::pair<int32_t, int32_t>> steps;
  for (const auto& [y, y_of_b] : members) {
    const std::pair<int32_t, bool>* pred = nullptr;
    for (const auto& x : members)
      if (before(x.first, y) &&
          (!pred || std::pair(last[x.first], x.first) > std::pair(last[pred->first], pred->first)))
        pred = &x;
    if (pred && pred->second != y_of_b) steps.push_back({pred->first, y});
  }
  std::sort(steps.begin(), steps.end(),
            [&](const auto& p, const auto& q) { return before(p.second, q.second); });
  return steps;
}

AssociationRecord join_track_segments(const SparseSDProblem& p, const TrackTable& tracks,
                                      const AssociationRecord& record, const SegmentOptions& options,
                                      SegmentSummary* summary) {
  options.validate();
  const int32_t S = p.S(), W = record.num_sensors;
  require(W == p.file_sensors, "join_track_segments", "the record's columns are not the problem's");
  const std::size_t K = record.num_tuples();
  {
    // --memory-budget (io/memory_budget.hpp), before the graph is built: per node its interval,
    // rows, held end, latest reports and adjacency list; per gated pair two adjacency entries (their growth
    // up to twice) and a hash entry (~64 bytes); per doubtful pair a hash entry; per tuple a target of S
    // member lists and at most two output rows.
    double pairs = 0.0, doubtful = 0.0;
    for (const SparsePairStatistic& st : p.pairs) pairs += static_cast<double>(st.size());
    for (const SparsePairStatistic& st : p.doubtful) doubtful += static_cast<double>(st.size());
    const double N = static_cast<double>(p.nodes());
    const double bytes =
        N * (3 * sizeof(double) + 3 * sizeof(std::size_t) + sizeof(LatestReports) + sizeof(std::vector<int>) +
             sizeof(int32_t)) +
        pairs * (4 * sizeof(std::pair<int32_t, double>) + 64.0) + doubtful * 64.0 +
        static_cast<double>(K) * (sizeof(Target) + S * (sizeof(std::vector<int32_t>) + sizeof(int32_t)) +
                                  2 * (W * sizeof(int32_t) + sizeof(double) + sizeof(int32_t)));
    require_memory_beside_held(0.0, bytes,
                               "the track segment pass (" + std::to_string(p.nodes()) + " local tracks, " +
                                   std::to_string(static_cast<int64_t>(pairs)) + " gated pairs)");
  }
  const SegmentGraph g = build_graph(p, tracks, options.coast_growth);

  // Targets: the assignment's tuples of ≥ 2 members.
  std::vector<Target> targets;
  std::vector<int32_t> target_of(p.nodes(), -1);
  for (std::size_t k = 0; k < K; ++k) {
    Target t;
    t.members.resize(S);
    t.tuple = k;
    int32_t n = 0;
    for (int32_t s = 0; s < S; ++s) {
      const int32_t track = record.tuples[k * W + p.sensor_columns[s]];
      if (track < 0) continue;
      const int32_t u = g.node(s, track);
      require(u >= 0, "join_track_segments", "a tuple names a track the problem does not hold");
      t.members[s].push_back(u);
      ++n;
    }
    if (n < 2) continue;
    for (const auto& m : t.members)
      for (int32_t u : m) target_of[u] = static_cast<int32_t>(targets.size());
    targets.push_back(std::move(t));
  }
  SegmentSummary sum;
  sum.targets = static_cast<int32_t>(targets.size());
  std::vector<uint8_t> dissolved(targets.size(), 0);  // merged into another target
  const TrackSplitOptions split;                      // the continuation test's allowance and gate
  const MergeGate merge_gate{split.manoeuvre_sigma * split.manoeuvre_sigma,
                             chi_square_quantile(split.gate_probability, tracks.dim())};
  const OverlapRule rule = make_overlap_rule(
      p, options, tracks,
      MergeGate{options.successor_manoeuvre_sigma * options.successor_manoeuvre_sigma, merge_gate.threshold});
  if (options.enabled)
    while (true) {
      ++sum.rounds;
      const int32_t j = join_round(g, targets, target_of, rule, &sum.duplicates);
      sum.joined += j;
      if (j > 0) continue;
      const int32_t m = merge_round(g, tracks, targets, target_of, dissolved, rule, merge_gate);
      sum.targets_merged += m;
      if (m == 0) break;
    }

  AssociationRecord out = record;
  out.tuples.clear();
  out.cost.clear();
  out.target.clear();
  int32_t next_target = 0;
  std::vector<int32_t> row(W, -1);
  auto emit = [&](const std::vector<int32_t>& nodes, double cost, int32_t target) {
    std::fill(row.begin(), row.end(), -1);
    for (int32_t u : nodes) {
      const int32_t s = p.sensor_of(u);
      row[p.sensor_columns[s]] = p.aligned[s].track[u - p.offset[s]];
    }
    out.tuples.insert(out.tuples.end(), row.begin(), row.end());
    out.cost.push_back(cost);
    out.target.push_back(target);
  };
  auto copy_tuple = [&](std::size_t k, int32_t target) {  // the assignment's tuple k, unchanged
    out.tuples.insert(out.tuples.end(), record.tuples.begin() + k * W, record.tuples.begin() + (k + 1) * W);
    out.cost.push_back(record.cost[k]);
    out.target.push_back(target);
  };
  std::vector<int32_t> target_of_tuple(K, -1);
  for (std::size_t t = 0; t < targets.size(); ++t)
    target_of_tuple[targets[t].tuple] = dissolved[t] ? -2 : static_cast<int32_t>(t);
  for (std::size_t k = 0; k < K; ++k) {
    const int32_t ti = target_of_tuple[k];
    if (ti == -2) continue;  // its target merged into an earlier one, which writes its members
    if (ti < 0) {
      // A tuple of one (or none): dropped when its track joined a target.
      std::vector<int32_t> nodes;
      for (int32_t s = 0; s < S; ++s) {
        const int32_t track = record.tuples[k * W + p.sensor_columns[s]];
        if (track >= 0) nodes.push_back(g.node(s, track));
      }
      if (nodes.size() == 1 && target_of[nodes[0]] >= 0) continue;
      copy_tuple(k, next_target++);
      continue;
    }
    const Target& t = targets[ti];
    const int32_t id = next_target++;
    if (!t.grew) {
      copy_tuple(k, id);
      continue;
    }
    ++sum.targets_joined;
    // Time slices at every segment's first and last report.
    std::vector<int32_t> all;
    std::vector<double> cuts;
    for (const auto& m : t.members)
      for (int32_t u : m) all.push_back(u), cuts.push_back(g.first[u]), cuts.push_back(g.last[u]);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    std::vector<uint8_t> written(all.size(), 0);
    std::vector<std::vector<int32_t>> slices;
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double mid = 0.5 * (cuts[c] + cuts[c + 1]);
      std::vector<int32_t> slice;
      for (const auto& m : t.members) {
        int32_t pick = -1;
        for (int32_t u : m)
          if (g.first[u] <= mid && mid <= g.last[u] && (pick < 0 || g.first[u] > g.first[pick])) pick = u;
        if (pick >= 0) slice.push_back(pick);
      }
      if (slice.size() < 2 || std::find(slices.begin(), slices.end(), slice) != slices.end()) continue;
      slices.push_back(slice);
      emit(slice, tuple_cost(g, slice), id);
      for (int32_t u : slice) written[std::find(all.begin(), all.end(), u) - all.begin()] = 1;
    }
    for (std::size_t q = 0; q < all.size(); ++q)
      if (!written[q]) emit({all[q]}, 0.0, id);
  }
  if (summary) *summary = sum;
  return out;
}

}  // namespace trackassoc
