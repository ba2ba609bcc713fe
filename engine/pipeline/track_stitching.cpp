// Fragment stitching by track segment association; see engine/pipeline/track_stitching.hpp.
#include "engine/pipeline/track_stitching.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "engine/pipeline/stitch_index.hpp"
#include "engine/pipeline/stitch_join_cost.hpp"
#include "engine/pipeline/stitch_swap_margin.hpp"
#include "io/memory_budget.hpp"
#include "kernels/assignment/lap_sparse.hpp"
#include "kernels/core/allocation_gauge.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"
#include "kernels/statistics/chi_square.hpp"
#include "kernels/statistics/histogram_density.hpp"
#include "kernels/statistics/mixture_weight.hpp"

namespace trackassoc {

void TrackStitchOptions::validate() const {
  require(std::isfinite(max_gap_s) && max_gap_s > 0.0, "stitching.max_gap_s", "expected a gap > 0 [s]");
  require(std::isfinite(max_overlap_s) && max_overlap_s >= 0.0, "stitching.max_overlap_s",
          "expected an overlap >= 0 [s]");
  require(std::isfinite(manoeuvre_sigma) && manoeuvre_sigma >= 0.0, "stitching.manoeuvre_sigma",
          "expected σ >= 0 [m/s²]");
  require(std::isfinite(turn_sigma) && turn_sigma >= 0.0, "stitching.turn_sigma", "expected σ >= 0 [m/s²]");
  require(turn_probability >= 0.0 && turn_probability <= 1.0, "stitching.turn_probability",
          "expected a probability in [0, 1]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "stitching.gate_probability",
          "expected a probability in (0, 1)");
  require(std::isfinite(swap_margin) && swap_margin >= 0.0, "stitching.swap_margin",
          "expected a margin >= 0 [nats] (0: off)");
  require(std::isfinite(turn_prior_joins) && turn_prior_joins >= 0.0, "stitching.turn_prior_joins",
          "expected a weight >= 0 [joins]");
  require(std::isfinite(quiet_sigma_prior) && quiet_sigma_prior > 0.0, "stitching.quiet_sigma_prior",
          "expected σ > 0 [m/s²]");
  require(std::isfinite(quiet_sigma_prior_sd) && quiet_sigma_prior_sd > 0.0, "stitching.quiet_sigma_prior_sd",
          "expected a log-standard deviation > 0");
  require(start_reports >= 1 && start_reports <= 16, "stitching.start_reports", "expected 1 to 16 reports");
  require(std::isfinite(gap_bin_s) && gap_bin_s >= 0.0, "stitching.gap_bin_s",
          "expected a bin >= 0 [s] (0: none)");
}

namespace {

struct Group {
  int32_t target = 0;
  std::size_t first = 0, last = 0;          // rows of the earliest and the latest report
  std::size_t start = 0;                    // the start's representative row (the header's x₁, P₁)
  uint32_t spans_begin = 0, spans_end = 0;  // its members' spans in Groups::spans
};

// One member (local track) of a group: its sensor and the times of its first and last report.
struct MemberSpan {
  int32_t sensor = 0;
  double first = 0.0, last = 0.0;
};

struct Groups {
  std::vector<Group> groups;
  std::vector<MemberSpan> spans;  // by group, in member (sensor, track) order
};

// The rows of a start track among which its representative is chosen: its earliest ones.
constexpr std::size_t kStartRows = 16;

// The groups of the rule, in increasing target number: each target number of `target` that has
// reports, with the rows of its earliest and latest report.
Groups groups_of(const TrackFile& file, const AssociationRecord& rec, const std::vector<int32_t>& target,
                 double q, std::size_t start_reports) {
  const TrackTable& t = file.tracks;
  const std::size_t S = static_cast<std::size_t>(rec.num_sensors), K = rec.num_tuples();
  // (sensor id, track, target number), sorted; of a key listed twice, the later tuple's number.
  struct Member {
    int32_t sensor, track, target;
    auto key() const { return std::pair{sensor, track}; }
  };
  std::vector<Member> members;
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t s = 0; s < S; ++s)
      if (rec.tuples[k * S + s] >= 0)
        members.push_back({file.sensors[s].id, rec.tuples[k * S + s], target[k]});
  std::stable_sort(members.begin(), members.end(),
                   [](const Member& a, const Member& b) { return a.key() < b.key(); });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (kept > 0 && members[kept - 1].key() == members[i].key()) --kept;
    members[kept++] = members[i];
  }
  members.resize(kept);
  std::vector<int32_t> numbers;
  numbers.reserve(members.size());
  for (const Member& m : members) numbers.push_back(m.target);
  std::sort(numbers.begin(), numbers.end());
  numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
  std::vector<Group> all(numbers.size());
  std::vector<char> seen(numbers.size(), 0);
  std::vector<int32_t> group_of_member(members.size());
  for (std::size_t m = 0; m < members.size(); ++m)
    group_of_member[m] = static_cast<int32_t>(
        std::lower_bound(numbers.begin(), numbers.end(), members[m].target) - numbers.begin());
  // Per sensor id, its members by track number: a table when its numbers are dense (at most 4
  // slots a member), else a binary search. Rows come in any order.
  struct Lookup {
    int32_t sensor = 0, first_track = 0;
    std::size_t begin = 0, end = 0;  // its members
    std::vector<int32_t> table;      // track − first_track -> member index or -1; empty: search
  };
  std::vector<Lookup> lookups;
  for (std::size_t i = 0; i < members.size();) {
    Lookup l;
    l.sensor = members[i].sensor, l.begin = i, l.first_track = members[i].track;
    while (i < members.size() && members[i].sensor == l.sensor) ++i;
    l.end = i;
    const int64_t span = static_cast<int64_t>(members[i - 1].track) - l.first_track + 1;
    if (span <= 4 * static_cast<int64_t>(l.end - l.begin) + 64) {
      l.table.assign(static_cast<std::size_t>(span), -1);
      for (std::size_t m = l.begin; m < l.end; ++m)
        l.table[static_cast<std::size_t>(members[m].track - l.first_track)] = static_cast<int32_t>(m);
    }
    lookups.push_back(std::move(l));
  }
  auto member_of = [&](const Lookup& l, int32_t track) -> std::ptrdiff_t {
    if (!l.table.empty()) {
      const int64_t i = static_cast<int64_t>(track) - l.first_track;
      return i < 0 || i >= static_cast<int64_t>(l.table.size()) ? -1 : l.table[static_cast<std::size_t>(i)];
    }
    const auto first = members.begin() + static_cast<std::ptrdiff_t>(l.begin),
               last = members.begin() + static_cast<std::ptrdiff_t>(l.end);
    const auto it =
        std::lower_bound(first, last, track, [](const Member& m, int32_t k) { return m.track < k; });
    return it == last || it->track != track ? -1 : it - members.begin();
  };
  // Calls visit(row, group index, member index) for every row of a member.
  auto for_each_member_row = [&](auto&& visit) {
    const Lookup* lookup = nullptr;
    for (std::size_t r = 0; r < t.size(); ++r) {
      if (lookup == nullptr || lookup->sensor != t.sensor[r]) {
        const auto it = std::lower_bound(lookups.begin(), lookups.end(), t.sensor[r],
                                         [](const Lookup& l, int32_t id) { return l.sensor < id; });
        if (it == lookups.end() || it->sensor != t.sensor[r]) continue;  // a sensor of no tuple
        lookup = &*it;
      }
      const std::ptrdiff_t m = member_of(*lookup, t.track[r]);
      if (m >= 0) visit(r, static_cast<std::size_t>(group_of_member[m]), static_cast<std::size_t>(m));
    }
  };
  std::vector<MemberSpan> span(members.size());
  for (std::size_t m = 0; m < members.size(); ++m)
    span[m] = {members[m].sensor, std::numeric_limits<double>::infinity(),
               -std::numeric_limits<double>::infinity()};
  for_each_member_row([&](std::size_t r, std::size_t g, std::size_t m) {
    Group& G = all[g];
    if (!seen[g]) {
      seen[g] = 1;
      G.target = numbers[g], G.first = G.last = r;
    }
    if (t.t[r] < t.t[G.first]) G.first = r;
    if (t.t[r] > t.t[G.last]) G.last = r;
    span[m].first = std::min(span[m].first, t.t[r]), span[m].last = std::max(span[m].last, t.t[r]);
  });
  // The start's representative: of the earliest kStartRows reports of the track that starts the
  // group, the one whose estimate, predicted back to the group's first report with the quiet model,
  // has the smallest covariance (ln det): a new track's first velocity is poor, a few reports later
  // it has converged. Chosen from the covariances alone, not from any residual.
  std::vector<std::array<std::size_t, kStartRows>> early(all.size());
  std::vector<uint8_t> n_early(all.size(), 0);
  for_each_member_row([&](std::size_t r, std::size_t g, std::size_t) {
    const std::size_t f = all[g].first;
    if (t.sensor[r] != t.sensor[f] || t.track[r] != t.track[f]) return;
    auto& e = early[g];
    std::size_t n = n_early[g];
    if (n == kStartRows && !(t.t[r] < t.t[e[n - 1]])) return;
    if (n < kStartRows) ++n;
    std::size_t i = n - 1;  // insertion, kept in time order
    for (; i > 0 && t.t[r] < t.t[e[i - 1]]; --i) e[i] = e[i - 1];
    e[i] = r;
    n_early[g] = static_cast<uint8_t>(n);
  });
  parallel_for_range(all.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t g = lo; g < hi; ++g) {
      if (!seen[g]) continue;
      double best = std::numeric_limits<double>::infinity();
      all[g].start = all[g].first;
      for (std::size_t i = 0; i < std::min<std::size_t>(n_early[g], start_reports); ++i) {
        const std::size_t r = early[g][i];
        const double log_det = predicted_log_det(t, r, t.t[all[g].first] - t.t[r], q);
        // Ties (equal information, as with a constant P and q = 0) keep the earlier report.
        if (log_det < best - 1e-9) best = log_det, all[g].start = r;
      }
    }
  });
  // The members' spans by group (a counting sort of the members by group, members with rows only).
  std::vector<uint32_t> begin(all.size() + 1, 0);
  for (std::size_t m = 0; m < members.size(); ++m)
    if (span[m].first <= span[m].last) ++begin[static_cast<std::size_t>(group_of_member[m]) + 1];
  std::partial_sum(begin.begin(), begin.end(), begin.begin());
  Groups out;
  out.spans.resize(begin.back());
  std::vector<uint32_t> next(begin.begin(), begin.end() - 1);
  for (std::size_t m = 0; m < members.size(); ++m)
    if (span[m].first <= span[m].last)
      out.spans[next[static_cast<std::size_t>(group_of_member[m])]++] = span[m];
  out.groups.reserve(all.size());
  for (std::size_t g = 0; g < all.size(); ++g)
    if (seen[g]) {
      all[g].spans_begin = begin[g], all[g].spans_end = begin[g + 1];
      out.groups.push_back(all[g]);
    }
  return out;
}

// Whether two groups hold tracks of one sensor that overlap by more than `overlap` seconds (the
// joined target would have two simultaneous tracks of that sensor).
bool share_a_sensor(const Groups& all, const Group& a, const Group& b, double overlap) {
  for (uint32_t i = a.spans_begin; i < a.spans_end; ++i)
    for (uint32_t j = b.spans_begin; j < b.spans_end; ++j) {
      const MemberSpan &u = all.spans[i], &v = all.spans[j];
      if (u.sensor == v.sensor && std::min(u.last, v.last) - std::max(u.first, v.first) > overlap)
        return true;
    }
  return false;
}

// One gated pair: end group, start group, its cost c₁₂ (with the window's n / V) and the two models'
// log-likelihood ratio at its gap.
struct Candidate {
  int32_t end, start;
  double cost;
  float turn_log_ratio;  // ln N(e; 0, S_turn) − ln N(e; 0, S_quiet), to re-weigh the mixture
};

}  // namespace

TrackStitchSummary stitch_fragments(const TrackFile& file, AssociationRecord& rec,
                                    const TrackStitchOptions& o) {
  o.validate();
  TrackStitchSummary summary;
  const int32_t S = rec.num_sensors;
  if (!o.enabled || S != static_cast<int32_t>(file.sensors.size()) || rec.num_tuples() == 0) return summary;
  const TrackTable& t = file.tracks;
  const std::size_t K = rec.num_tuples();
  // --memory-budget (io/memory_budget.hpp), before anything is allocated: per tuple (at most one
  // group each) its group, the start representative's scratch, the start orderings, the start
  // density's scratch (two doubles) and the index (StitchStartIndex: ~100 bytes a start); per member its key,
  // span and group; the candidates are counted as they are found (below).
  std::size_t members = 0;
  for (int32_t track : rec.tuples) members += track >= 0;
  const double per_group = sizeof(Group) + kStartRows * sizeof(std::size_t) + 2 + 8 * sizeof(double) + 100.0 +
                           sizeof(int32_t) + 4 * sizeof(std::size_t),
               per_member = 3 * sizeof(int32_t) + sizeof(MemberSpan) + 2 * sizeof(int32_t);
  const std::string what = "fragment stitching (" + std::to_string(K) + " tuples)";
  require_memory_beside_held(
      0.0, static_cast<double>(K) * per_group + static_cast<double>(members) * per_member, what);
  const double beside = held_or_resident(0.0);
  AllocationGauge gauge(
      [&](double stage_bytes, double, bool) { require_memory_beside(beside, stage_bytes, what); });
  std::vector<int32_t> target = rec.target;
  if (target.empty()) {  // every tuple its own target
    target.resize(K);
    std::iota(target.begin(), target.end(), 0);
  }
  const Groups grouped = groups_of(file, rec, target, o.manoeuvre_sigma * o.manoeuvre_sigma,
                                   static_cast<std::size_t>(o.start_reports));
  const std::vector<Group>& groups = grouped.groups;
  const std::size_t G = groups.size();
  summary.groups = static_cast<int32_t>(G);
  std::vector<std::size_t> by_start(G);
  std::iota(by_start.begin(), by_start.end(), 0);
  std::sort(by_start.begin(), by_start.end(),
            [&](std::size_t a, std::size_t b) { return t.t[groups[a].first] < t.t[groups[b].first]; });
  // "Different targets": the density f of the groups' start states (start_density_bins: a
  // histogram per state component, else uniform over their box); ln f at each group's start.
  const int D = t.dim();
  std::vector<double> log_density(G, 0.0);
  for (int i = 0; i < D; ++i) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Group& g : groups)
      lo = std::min(lo, t.state[i][g.start]), hi = std::max(hi, t.state[i][g.start]);
    const double width = std::max(hi - lo, 1.0);
    if (!o.start_density_bins || !std::isfinite(width)) {
      for (double& l : log_density) l -= std::log(width);
      continue;
    }
    // Each start against the histogram of the other starts (kernels/statistics/histogram_density.hpp).
    std::vector<double> component(G);
    for (std::size_t g = 0; g < G; ++g) component[g] = t.state[i][groups[g].start];
    const std::vector<double> log_h = leave_one_out_log_density(component);
    for (std::size_t g = 0; g < G; ++g) log_density[g] += log_h[g];
  }
  // Candidates (rows: ends, columns: starts): for each end, the starts of its window that the
  // index (engine/pipeline/stitch_index.hpp) does not exclude, in start-time order, gated. The
  // index holds the starts' representatives (the rows join_cost's pre-gate takes), in their time
  // order; a start of the window has its representative at most `transient` after its first report.
  const double gate = chi_square_quantile(o.gate_probability, D);
  // The turn model's weight is learnt from the first joins (below) unless fixed or degenerate; it
  // and the gap prior revise the costs after the first assignment, which then keeps every gated pair.
  const bool learn = o.learn_turn_probability && o.turn_probability > 0.0 && o.turn_probability < 1.0;
  const bool costs_revised = learn || o.gap_bin_s > 0.0;
  std::vector<double> start_times(G);  // by start position
  std::vector<int32_t> start_position(G);
  double transient = 0.0;
  for (std::size_t p = 0; p < G; ++p) {
    const Group& g = groups[by_start[p]];
    start_times[p] = t.t[g.first];
    start_position[by_start[p]] = static_cast<int32_t>(p);
    transient = std::max(transient, t.t[g.start] - t.t[g.first]);
  }
  std::vector<std::size_t> by_representative(by_start);
  std::stable_sort(by_representative.begin(), by_representative.end(),
                   [&](std::size_t a, std::size_t b) { return t.t[groups[a].start] < t.t[groups[b].start]; });
  std::vector<std::size_t> start_rows(G);
  for (std::size_t p = 0; p < G; ++p) start_rows[p] = groups[by_representative[p]].start;
  const StitchStartIndex index(t, start_rows, o.turn_sigma * o.turn_sigma, gate, o.max_overlap_s,
                               o.max_gap_s + transient);
  start_rows = {};
  constexpr std::size_t kBlock = 1024;  // ends per task; the blocks are concatenated in order
  std::vector<std::vector<Candidate>> kept((G + kBlock - 1) / kBlock);
  std::vector<int64_t> gated((G + kBlock - 1) / kBlock, 0);  // gated pairs per block of ends
  parallel_for_range(kept.size(), 1, [&](std::size_t first_block, std::size_t last_block) {
    std::vector<int32_t> near;
    for (std::size_t k = first_block; k < last_block; ++k)
      for (std::size_t a = k * kBlock; a < std::min(G, (k + 1) * kBlock); ++a) {
        const double end = t.t[groups[a].last];
        // "A different target": any of the n starts of the window, each uniform over the box, so
        // the density of the alternative is n / V (the density of new starts of MHT's track score).
        // n: the starts of the window [L, end + max_gap_s], L = end − max_overlap_s. A start before
        // the window (a transient overlap) is drawn from a wider set: those and the starts before L
        // whose representative is not, #(first < L) − #(representative < L) (a representative never
        // precedes its start).
        const double window_start = end - o.max_overlap_s;
        const auto first = std::lower_bound(start_times.begin(), start_times.end(), window_start);
        const auto last = std::upper_bound(first, start_times.end(), end + o.max_gap_s);
        // (#(representative < L) is where the index's window, over the representatives, begins.)
        const std::ptrdiff_t n = last - first,
                             n_before = (first - start_times.begin()) - index.window(end).first;
        const double log_n = std::log(std::max<double>(1.0, static_cast<double>(n))),
                     log_n_transient = std::log(std::max<double>(1.0, static_cast<double>(n + n_before)));
        index.query(t, groups[a].last, near);
        for (int32_t& p : near) p = start_position[by_representative[static_cast<std::size_t>(p)]];
        std::sort(near.begin(), near.end());
        for (int32_t p : near) {
          const std::size_t b = by_start[static_cast<std::size_t>(p)];
          const double start = start_times[static_cast<std::size_t>(p)];
          if (start > end + o.max_gap_s) continue;
          // A start before the window overlaps the end by more than max_overlap_s, while its
          // representative is within it: the overlap lies in the new track's transient.
          if (start < window_start &&
              (!o.transient_overlap || share_a_sensor(grouped, groups[a], groups[b], o.max_overlap_s)))
            continue;
          if (b == a || t.t[groups[b].last] <= end) continue;  // b must go on after a ends
          if (t.t[groups[a].first] >= start) continue;         // and start after a starts
          double turn_log_ratio = 0.0;
          const double c = join_cost(t, groups[a].last, groups[b].start, o, gate, &turn_log_ratio);
          if (!std::isfinite(c)) continue;
          ++gated[k];
          const double cost = c + (start < window_start ? log_n_transient : log_n) + log_density[b];
          if (cost < 0.0 || costs_revised)
            gauged_push_back(
                kept[k],
                {static_cast<int32_t>(a), static_cast<int32_t>(b), cost, static_cast<float>(turn_log_ratio)},
                &gauge);
        }
      }
  });
  // The gated pairs (of positive evidence without the gap prior), in order of their ends (then of
  // their starts' times).
  std::vector<Candidate> candidates;
  std::size_t found = 0;
  for (const auto& block : kept) found += block.size();
  gauged_reserve(candidates, found, &gauge);
  for (auto& block : kept) {
    candidates.insert(candidates.end(), block.begin(), block.end());
    gauge.release(static_cast<double>(block.capacity() * sizeof(Candidate)));
    block = {};
  }
  for (int64_t n : gated) summary.candidates += static_cast<int32_t>(n);
  // The pairs of positive evidence enter one LAP, at their candidates' costs.
  auto eligible = [](const Candidate& k) { return k.cost < 0.0; };
  auto solve = [&] {
    std::vector<int32_t> row_start{0}, col;
    std::vector<double> cost;
    std::size_t next = 0;
    for (std::size_t a = 0; a < G; ++a) {
      for (; next < candidates.size() && candidates[next].end == static_cast<int32_t>(a); ++next) {
        const Candidate& k = candidates[next];
        if (!eligible(k)) continue;
        col.push_back(k.start);
        cost.push_back(k.cost);
      }
      row_start.push_back(static_cast<int32_t>(col.size()));
    }
    LapResult r;
    if (col.empty()) return r;
    SparseCostView view;
    view.rows = view.cols = static_cast<int32_t>(G);
    view.row_start = row_start;
    view.col = col;
    view.cost = cost;
    LapOptions lap;
    lap.allow_unassigned = true;  // "no successor" / "no predecessor" at cost 0
    return solve_gated_lap(view, lap);
  };
  LapResult joins = solve();
  if (joins.row_to_col.empty()) return summary;
  if (learn) {
    // The turn model's weight, learnt from the first joins (the header's empirical Bayes) as a
    // function of the span s that the two predictions bridge, π(s) = 1 − (1 − π_c) e^{−λ s}
    // (kernels/statistics/mixture_weight.hpp), and the candidates' costs under it: −ln[(1 − π(s)) +
    // π(s) e^d] instead of −ln[(1 − π) + π e^d] (the quiet density factored out, d = turn_log_ratio).
    auto span_of = [&](const Candidate& k) {
      return std::fabs(t.t[groups[static_cast<std::size_t>(k.start)].start] -
                       t.t[groups[static_cast<std::size_t>(k.end)].last]);
    };
    std::vector<float> joined, spans;
    std::vector<JoinRows> rows;
    for (const Candidate& k : candidates)
      if (joins.row_to_col[static_cast<std::size_t>(k.end)] == k.start) {
        joined.push_back(k.turn_log_ratio), spans.push_back(static_cast<float>(span_of(k)));
        rows.push_back(
            {groups[static_cast<std::size_t>(k.end)].last, groups[static_cast<std::size_t>(k.start)].start});
      }
    const double pi = o.turn_probability;
    // With the quiet model's σ_a when it is learnt too (stitch_join_cost.hpp, learn_quiet_sigma).
    const bool learn_sigma = o.learn_quiet_sigma && o.manoeuvre_sigma > 0.0;
    const QuietModelFit fit =
        learn_sigma
            ? learn_quiet_sigma(t, rows, spans, o)
            : QuietModelFit{o.manoeuvre_sigma, span_mixture_weight(joined, spans, pi, o.turn_prior_joins)};
    const SpanMixtureWeight& learnt = fit.weight;
    summary.turn_probability = learnt.at(learnt.mean_span);
    summary.manoeuvre_interval_s = learnt.rate > 0.0 ? 1.0 / learnt.rate : 0.0;
    if (learn_sigma) summary.quiet_sigma = fit.sigma;
    const JoinCostRevision revision(o, fit.sigma);
    parallel_for_range(candidates.size(), 1024, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) {
        Candidate& k = candidates[i];
        const double now = std::min(learnt.at(span_of(k)), 1.0 - 1e-16);  // π_c > 0: π > 0
        k.cost += revision(t, groups[static_cast<std::size_t>(k.end)].last,
                           groups[static_cast<std::size_t>(k.start)].start, now, k.turn_log_ratio);
      }
    });
  }
  if (o.gap_bin_s > 0.0) {
    // The gap prior: the same target's gaps follow its fades and re-initiations, a different
    // target's start is uniform over the window W. Its density, a histogram of the first joins'
    // gaps (Laplace-smoothed), turns into the factor W·p(g) of the likelihood ratio.
    const double W = o.max_overlap_s + o.max_gap_s;
    const std::size_t B = static_cast<std::size_t>(std::ceil(W / o.gap_bin_s));
    auto bin_of = [&](double g) {
      return std::min(B - 1, static_cast<std::size_t>(std::max(0.0, (g + o.max_overlap_s) / o.gap_bin_s)));
    };
    auto gap_of = [&](std::size_t a, std::size_t b) { return t.t[groups[b].first] - t.t[groups[a].last]; };
    std::vector<double> count(B, 1.0);
    double total = static_cast<double>(B);
    for (std::size_t a = 0; a < G; ++a)
      if (joins.row_to_col[a] >= 0)
        count[bin_of(gap_of(a, static_cast<std::size_t>(joins.row_to_col[a])))] += 1.0, total += 1.0;
    std::vector<double> log_factor(B);
    for (std::size_t k = 0; k < B; ++k) {
      const double width = std::min(o.gap_bin_s, W - static_cast<double>(k) * o.gap_bin_s);
      log_factor[k] = std::log(W * count[k] / (total * width));
    }
    for (Candidate& k : candidates)  // the costs with the prior, in place (the first joins are counted)
      k.cost -=
          log_factor[bin_of(gap_of(static_cast<std::size_t>(k.end), static_cast<std::size_t>(k.start)))];
  }
  if (costs_revised) {
    joins = solve();
    if (joins.row_to_col.empty()) return summary;
  }
  if (o.swap_margin > 0.0) {
    // The swap margin (engine/pipeline/stitch_swap_margin.hpp): a join that one exchange with a
    // rival nearly matches is left unmade.
    // The candidates that entered the LAP (16 bytes each, at most every one), their index by start
    // (8) and the margins' per-group arrays (4 of 8 bytes a group), counted before they are allocated.
    const double bytes = 24.0 * static_cast<double>(candidates.size()) + 32.0 * static_cast<double>(G);
    gauge.add(bytes);
    std::vector<int32_t> ends, starts;
    std::vector<double> costs;
    for (const Candidate& k : candidates)
      if (eligible(k)) ends.push_back(k.end), starts.push_back(k.start), costs.push_back(k.cost);
    const std::vector<double> margin =
        stitch_swap_margins(static_cast<int32_t>(G), {ends, starts, costs}, joins.row_to_col);
    for (std::size_t a = 0; a < G; ++a)
      if (margin[a] < o.swap_margin) joins.row_to_col[a] = -1;
    gauge.release(bytes);
  }
  // Union-find over group indices; the root keeps the earliest group's target number.
  std::vector<std::size_t> parent(G);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t a = 0; a < G; ++a) {
    if (joins.row_to_col[a] < 0) continue;
    const std::size_t ra = find(a), rb = find(static_cast<std::size_t>(joins.row_to_col[a]));
    if (ra == rb) continue;
    if (t.t[groups[rb].first] < t.t[groups[ra].first])  // the root is the group that starts first
      parent[ra] = rb;
    else
      parent[rb] = ra;
    ++summary.stitches;
  }
  if (summary.stitches == 0) return summary;
  // groups is in increasing target number: a binary search finds a tuple's group.
  std::vector<int32_t> renumber(G);
  for (std::size_t g = 0; g < G; ++g) renumber[g] = groups[find(g)].target;
  for (auto& number : target) {
    const auto it = std::lower_bound(groups.begin(), groups.end(), number,
                                     [](const Group& g, int32_t n) { return g.target < n; });
    if (it != groups.end() && it->target == number)
      number = renumber[static_cast<std::size_t>(it - groups.begin())];
  }
  rec.target = std::move(target);
  return summary;
}

}  // namespace trackassoc
