#include "engine/pipeline/tuple_decoding.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trackassoc {

namespace {

constexpr std::array<std::pair<int, int>, 3> kSensorPairs{{{0, 1}, {1, 2}, {0, 2}}};

}  // namespace

void split_tuple(const GatedLambda& lambda, const std::array<int32_t, 3>& t, bool all_pairs,
                 const std::function<double(double, double, double)>& triple_cost, const EmitTuple& emit,
                 std::array<std::vector<int32_t>, 3>& left_over) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::array<double, 3> l{kNaN, kNaN, kNaN};  // by sensor pair q
  for (int q = 0; q < 3; ++q) {
    const auto [a, b] = kSensorPairs[q];
    if (t[a] >= 0 && t[b] >= 0) l[q] = lambda(q, t[a], t[b]);
  }
  if (!std::isnan(l[0]) && !std::isnan(l[1]) && (!all_pairs || !std::isnan(l[2]))) {
    emit(t, triple_cost(l[0], l[1], all_pairs ? l[2] : kNaN));
    return;
  }
  // Best gated-in pair by λ (the first on ties, in the order 0–1, 1–2, 0–2).
  int best = -1;
  for (int q = 0; q < 3; ++q)
    if (!std::isnan(l[q]) && (best < 0 || l[q] < l[best])) best = q;
  std::array<bool, 3> used{false, false, false};
  if (best >= 0) {
    const auto [a, b] = kSensorPairs[best];
    std::array<int32_t, 3> part{kNoTrack, kNoTrack, kNoTrack};
    part[a] = t[a];
    part[b] = t[b];
    emit(part, l[best]);
    used[a] = used[b] = true;
  }
  for (int d = 0; d < 3; ++d)
    if (!used[d] && t[d] >= 0) left_over[d].push_back(t[d]);
}

void pair_leftovers(const GatedLambda& lambda, const std::array<std::vector<int32_t>, 3>& leftovers,
                    const EmitTuple& emit) {
  struct Candidate {
    double lambda;
    int q;
    std::size_t xa, xb;  // positions in leftovers[a], leftovers[b]
  };
  std::vector<Candidate> pairs;
  for (int q = 0; q < 3; ++q) {
    const auto [a, b] = kSensorPairs[q];
    for (std::size_t xa = 0; xa < leftovers[a].size(); ++xa)
      for (std::size_t xb = 0; xb < leftovers[b].size(); ++xb) {
        const double l = lambda(q, leftovers[a][xa], leftovers[b][xb]);
        if (!std::isnan(l)) pairs.push_back({l, q, xa, xb});
      }
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Candidate& x, const Candidate& y) { return x.lambda < y.lambda; });
  std::array<std::vector<char>, 3> done;
  for (int d = 0; d < 3; ++d) done[d].assign(leftovers[d].size(), 0);
  for (const Candidate& c : pairs) {
    const auto [a, b] = kSensorPairs[c.q];
    if (done[a][c.xa] || done[b][c.xb]) continue;
    done[a][c.xa] = done[b][c.xb] = 1;
    std::array<int32_t, 3> part{kNoTrack, kNoTrack, kNoTrack};
    part[a] = leftovers[a][c.xa];
    part[b] = leftovers[b][c.xb];
    emit(part, c.lambda);
  }
  for (int d = 0; d < 3; ++d)
    for (std::size_t x = 0; x < leftovers[d].size(); ++x)
      if (!done[d][x]) {
        std::array<int32_t, 3> single{kNoTrack, kNoTrack, kNoTrack};
        single[d] = leftovers[d][x];
        emit(single, 0.0);
      }
}

}  // namespace trackassoc
