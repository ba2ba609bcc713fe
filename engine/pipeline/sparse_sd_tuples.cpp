// A giant component solved over its allowed tuples (engine/pipeline/sparse_sd_tuples.hpp).
#include "engine/pipeline/sparse_sd_tuples.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <utility>
#include <vector>

namespace trackassoc {

namespace {

// Bytes per listed tuple besides its S indices and its cost: the hash set's node and bucket.
constexpr double kHashBytesPerTuple = 48.0;
// The list's vectors grow by doubling: up to twice their size is held while one is moved.
constexpr double kGrowth = 2.0;

}  // namespace

std::optional<TupleListSD> list_component_tuples(const SDComponentView& v, bool all_pairs, double max_bytes) {
  const int32_t S = v.S;
  TupleListSD list;
  list.n.resize(S);
  for (int32_t s = 0; s < S; ++s) list.n[s] = static_cast<int32_t>(v.tracks[s].size());
  // Gated neighbours of every (sensor, index), from the link matrices. A doubtful pair's entry
  // (engine/pipeline/tuple_cost.hpp) is no neighbour: it links nothing, so a tuple grown through it
  // alone is refused, and one its new member joins through a gated pair is found from that pair.
  std::vector<std::vector<std::vector<std::pair<int32_t, int32_t>>>> adj(S);
  for (int32_t s = 0; s < S; ++s) adj[s].resize(list.n[s]);
  for (int32_t a = 0; a < S; ++a)
    for (int32_t b = a + 1; b < S; ++b)
      v.link[static_cast<std::size_t>(a) * S + b].for_each([&](int32_t i, int32_t j, double entry) {
        if (is_doubtful_pair_entry(entry)) return;
        adj[a][i].emplace_back(b, j);
        adj[b][j].emplace_back(a, i);
      });
  const double per_tuple =
      kGrowth * (static_cast<double>(S) * sizeof(int32_t) + sizeof(double)) + kHashBytesPerTuple;
  double tracks = 0.0;
  for (int32_t s = 0; s < S; ++s) tracks += list.n[s];
  const double max_tuples = kMaxListedTuplesPerTrack * tracks;
  auto row = [&](std::size_t t) { return list.tuples.data() + t * S; };
  struct Hash {
    const TupleListSD* l;
    int32_t S;
    std::size_t operator()(std::size_t t) const {
      std::size_t h = 1469598103934665603ull;
      for (int32_t s = 0; s < S; ++s)
        h = (h ^ static_cast<std::size_t>(l->tuples[t * S + s] + 1)) * 1099511628211ull;
      return h;
    }
  };
  struct Equal {
    const TupleListSD* l;
    int32_t S;
    bool operator()(std::size_t x, std::size_t y) const {
      for (int32_t s = 0; s < S; ++s)
        if (l->tuples[x * S + s] != l->tuples[y * S + s]) return false;
      return true;
    }
  };
  std::unordered_set<std::size_t, Hash, Equal> seen(0, Hash{&list, S}, Equal{&list, S});
  for (int32_t s = 0; s < S; ++s)
    for (int32_t i = 0; i < list.n[s]; ++i) {
      list.tuples.resize(list.tuples.size() + S, kNoTrack);
      list.tuples[list.tuples.size() - S + s] = i;
      list.cost.push_back(0.0);
      seen.insert(list.size() - 1);
    }
  std::vector<std::pair<int32_t, int32_t>> members;
  std::vector<int32_t> base(S);
  for (std::size_t t = 0; t < list.size(); ++t) {
    const auto listed = static_cast<double>(list.size());
    if (listed * per_tuple > max_bytes || listed > max_tuples) return std::nullopt;
    std::copy_n(row(t), S, base.begin());  // row(t) moves as the list grows
    members.clear();
    for (int32_t s = 0; s < S; ++s)
      if (base[s] >= 0) members.emplace_back(s, base[s]);
    const std::size_t k = members.size();
    for (std::size_t m = 0; m < k; ++m)
      for (const auto& [s2, j] : adj[members[m].first][members[m].second]) {
        if (base[s2] >= 0) continue;
        // A candidate: t with j on sensor s2. Its cost (+inf: a coexisting member failed the gate).
        members.emplace_back(s2, j);
        const double c = sd_component_tuple_cost(v, members, all_pairs);
        members.pop_back();
        if (!std::isfinite(c)) continue;
        const std::size_t u = list.size();
        list.tuples.insert(list.tuples.end(), base.begin(), base.end());
        list.tuples[u * S + s2] = j;
        list.cost.push_back(c);
        if (!seen.insert(u).second) {
          list.tuples.resize(u * S);
          list.cost.pop_back();
        }
      }
  }
  return list;
}

SDComponentResult solve_sd_component_by_tuples(const SDComponentView& v, const TupleListSD& list,
                                               bool all_pairs, const LagrangianOptions& options) {
  const SolutionSD sol = solve_lagrangian_sd_tuples(list, options);
  SDComponentResult r;
  const int32_t S = v.S;
  std::vector<std::pair<int32_t, int32_t>> members;
  for (std::size_t k = 0; k < sol.num_tuples(); ++k) {
    std::vector<int32_t> tuple;
    members.clear();
    for (int32_t s = 0; s < S; ++s)
      if (const int32_t i = sol.tuples[k * S + s]; i >= 0) {
        tuple.push_back(v.node[s][i]);
        members.emplace_back(s, i);
      }
    r.tuples.push_back(std::move(tuple));
    r.costs.push_back(sd_component_tuple_cost(v, members, all_pairs));
  }
  r.objective = sol.summary.objective;
  r.lower_bound = sol.summary.lower_bound;
  r.termination = sol.summary.termination;
  r.listed_tuples = list.size();
  return r;
}

}  // namespace trackassoc
