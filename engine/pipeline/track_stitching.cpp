// Fragment stitching; see engine/pipeline/track_stitching.hpp.
#include "engine/pipeline/track_stitching.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "engine/pipeline/track_hygiene.hpp"
#include "kernels/core/error.hpp"
#include "kernels/statistics/chi_square.hpp"

namespace trackassoc {

void TrackStitchOptions::validate() const {
  require(std::isfinite(max_gap_s) && max_gap_s > 0.0, "stitching.max_gap_s", "expected a gap > 0 [s]");
  require(std::isfinite(max_overlap_s) && max_overlap_s >= 0.0, "stitching.max_overlap_s",
          "expected an overlap >= 0 [s]");
  require(std::isfinite(manoeuvre_sigma) && manoeuvre_sigma >= 0.0, "stitching.manoeuvre_sigma",
          "expected σ >= 0 [m/s²]");
  require(gate_probability > 0.0 && gate_probability < 1.0, "stitching.gate_probability",
          "expected a probability in (0, 1)");
}

namespace {

struct Group {
  int32_t target = 0;
  std::size_t first = 0, last = 0;  // rows of the earliest and the latest report
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
  std::vector<int32_t> target = rec.target;
  if (target.empty()) {  // every tuple its own target
    target.resize(K);
    std::iota(target.begin(), target.end(), 0);
  }
  // (sensor id, track) -> target number.
  std::map<std::pair<int32_t, int32_t>, int32_t> target_of;
  for (std::size_t k = 0; k < K; ++k)
    for (int32_t s = 0; s < S; ++s)
      if (rec.tuples[k * S + s] >= 0) target_of[{file.sensors[s].id, rec.tuples[k * S + s]}] = target[k];
  std::map<int32_t, Group> by_target;
  for (std::size_t r = 0; r < t.size(); ++r) {
    const auto it = target_of.find({t.sensor[r], t.track[r]});
    if (it == target_of.end()) continue;
    auto [g, fresh] = by_target.try_emplace(it->second);
    Group& G = g->second;
    if (fresh) G.target = it->second, G.first = G.last = r;
    if (t.t[r] < t.t[G.first]) G.first = r;
    if (t.t[r] > t.t[G.last]) G.last = r;
  }
  std::vector<const Group*> groups;
  for (const auto& [k, g] : by_target) groups.push_back(&g);
  summary.groups = static_cast<int32_t>(groups.size());
  std::vector<std::size_t> by_start(groups.size());
  std::iota(by_start.begin(), by_start.end(), 0);
  std::sort(by_start.begin(), by_start.end(),
            [&](std::size_t a, std::size_t b) { return t.t[groups[a]->first] < t.t[groups[b]->first]; });
  std::vector<double> starts;
  for (std::size_t i : by_start) starts.push_back(t.t[groups[i]->first]);
  const double gate = chi_square_quantile(o.gate_probability, t.dim());
  const double q = o.manoeuvre_sigma * o.manoeuvre_sigma;
  // Gated pairs (predecessor, successor), indices into groups.
  std::vector<std::pair<std::size_t, std::size_t>> gated;
  for (std::size_t a = 0; a < groups.size(); ++a) {
    const double end = t.t[groups[a]->last];
    auto lo = std::lower_bound(starts.begin(), starts.end(), end - o.max_overlap_s);
    for (auto it = lo; it != starts.end() && *it <= end + o.max_gap_s; ++it) {
      const std::size_t b = by_start[static_cast<std::size_t>(it - starts.begin())];
      if (b == a || t.t[groups[b]->last] <= end) continue;           // b must go on after a ends
      if (t.t[groups[a]->first] >= t.t[groups[b]->first]) continue;  // and start after a starts
      if (continuation_statistic(t, groups[a]->last, groups[b]->first, q) <= gate) gated.push_back({a, b});
    }
  }
  summary.candidates = static_cast<int32_t>(gated.size());
  // Ambiguous: another gated successor of a that coexists with b, or another gated predecessor
  // of b that coexists with a. (A later successor that starts after b ends is not a rival: it
  // may be the same target again, after b.)
  auto coexist = [&](std::size_t x, std::size_t y) {
    return std::min(t.t[groups[x]->last], t.t[groups[y]->last]) -
               std::max(t.t[groups[x]->first], t.t[groups[y]->first]) >
           o.max_overlap_s;
  };
  std::vector<std::vector<std::size_t>> successors(groups.size()), predecessors(groups.size());
  for (const auto& [a, b] : gated) successors[a].push_back(b), predecessors[b].push_back(a);
  // Of the unambiguous pairs, each group keeps its earliest successor and its latest predecessor.
  const std::size_t none = groups.size();
  std::vector<std::size_t> next(groups.size(), none), previous(groups.size(), none);
  for (const auto& [a, b] : gated) {
    bool ambiguous = false;
    for (std::size_t b2 : successors[a]) ambiguous |= b2 != b && coexist(b, b2);
    for (std::size_t a2 : predecessors[b]) ambiguous |= a2 != a && coexist(a, a2);
    if (ambiguous) continue;
    if (next[a] == none || t.t[groups[b]->first] < t.t[groups[next[a]]->first]) next[a] = b;
    if (previous[b] == none || t.t[groups[a]->last] > t.t[groups[previous[b]]->last]) previous[b] = a;
  }
  // Union-find over group indices; the root keeps the earliest group's target number.
  std::vector<std::size_t> parent(groups.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [a, b] : gated) {
    if (next[a] != b || previous[b] != a) continue;
    const std::size_t ra = find(a), rb = find(b);
    if (ra == rb) continue;
    // The root is the group that starts first.
    if (t.t[groups[rb]->first] < t.t[groups[ra]->first])
      parent[ra] = rb;
    else
      parent[rb] = ra;
    ++summary.stitches;
  }
  if (summary.stitches == 0) return summary;
  std::map<int32_t, int32_t> renumber;
  for (std::size_t g = 0; g < groups.size(); ++g) renumber[groups[g]->target] = groups[find(g)]->target;
  for (auto& number : target) {
    const auto it = renumber.find(number);
    if (it != renumber.end()) number = it->second;
  }
  rec.target = std::move(target);
  return summary;
}

}  // namespace trackassoc
