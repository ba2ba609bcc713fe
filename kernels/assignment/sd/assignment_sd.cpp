#include "kernels/assignment/sd/assignment_sd.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "kernels/assignment/lap.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool all_dummy(std::span<const int32_t> t) {
  return std::all_of(t.begin(), t.end(), [](int32_t x) { return x < 0; });
}

}  // namespace

CostTensorSD::CostTensorSD(std::vector<int32_t> sizes, float fill, std::size_t max_entries)
    : n(std::move(sizes)) {
  require(n.size() >= 2, "CostTensorSD", "needs at least 2 sensors, got " + std::to_string(n.size()));
  std::size_t total = 1;
  stride.assign(n.size(), 0);
  for (std::size_t s = n.size(); s-- > 0;) {
    require(n[s] >= 0, "CostTensorSD", "sensor " + std::to_string(s) + " has a negative track count");
    stride[s] = total;
    const std::size_t extent = static_cast<std::size_t>(n[s]) + 1;
    require(total <= max_entries / extent, "CostTensorSD",
            "the dense S-D tensor would exceed " + std::to_string(max_entries) +
                " entries; use fewer sensors or tracks, or the sparse form (associate --sparse)");
    total *= extent;
  }
  cost.assign(total, fill);
}

void CostTensorSD::validate() const {
  require(n.size() >= 2 && stride.size() == n.size(), "CostTensorSD", "inconsistent sizes");
  std::size_t total = 1;
  for (std::size_t s = n.size(); s-- > 0;) {
    require(stride[s] == total, "CostTensorSD", "inconsistent strides");
    total *= static_cast<std::size_t>(n[s]) + 1;
  }
  require(cost.size() == total, "CostTensorSD",
          "cost has " + std::to_string(cost.size()) + " entries, expected " + std::to_string(total));
  for (std::size_t e = 0; e < cost.size(); ++e)
    require(!std::isnan(cost[e]), "CostTensorSD", "NaN cost at entry " + std::to_string(e));
}

double assignment_cost_sd(const CostTensorSD& c, std::span<const int32_t> tuples) {
  const std::size_t S = c.n.size();
  double sum = 0.0;
  for (std::size_t k = 0; k + S <= tuples.size(); k += S) sum += c.at(tuples.subspan(k, S));
  return sum;
}

bool is_valid_assignment_sd(const CostTensorSD& c, std::span<const int32_t> tuples) {
  const std::size_t S = c.n.size();
  if (tuples.size() % S != 0) return false;
  std::vector<std::vector<char>> used(S);
  for (std::size_t s = 0; s < S; ++s) used[s].assign(c.n[s], 0);
  for (std::size_t k = 0; k < tuples.size(); k += S) {
    const auto t = tuples.subspan(k, S);
    if (all_dummy(t) || !std::isfinite(c.at(t))) return false;
    for (std::size_t s = 0; s < S; ++s) {
      if (t[s] == kNoTrack) continue;
      if (t[s] < 0 || t[s] >= c.n[s] || used[s][t[s]]) return false;
      used[s][t[s]] = 1;
    }
  }
  for (const auto& u : used)
    if (std::find(u.begin(), u.end(), 0) != u.end()) return false;
  return true;
}

void finish_summary_sd(const CostTensorSD& c, std::span<const int32_t> tuples, double lower_bound,
                       SolverSummary& summary) {
  summary.feasible = is_valid_assignment_sd(c, tuples);
  summary.objective = summary.feasible ? assignment_cost_sd(c, tuples) : kInf;
  set_bound_and_gap(summary, lower_bound);
}

DimensionMatch match_dimension(std::span<const double> e, std::span<const double> e_new, int32_t m,
                               int32_t n) {
  DimensionMatch out;
  out.tuple_index.assign(m, kNoTrack);
  const int32_t size = m + n;
  if (size == 0) return out;
  // Rows: the m tuples, then one "new tuple" row per index. Columns: the n indices, then one
  // "no index" column per tuple. The new-tuple rows take the "no index" columns at zero cost.
  std::vector<double> a(static_cast<std::size_t>(size) * size, kInf);
  for (int32_t r = 0; r < m; ++r) {
    double* row = a.data() + static_cast<std::size_t>(r) * size;
    for (int32_t col = 0; col < n; ++col) row[col] = e[static_cast<std::size_t>(r) * (n + 1) + col];
    row[n + r] = e[static_cast<std::size_t>(r) * (n + 1) + n];
  }
  for (int32_t col = 0; col < n; ++col) {
    double* row = a.data() + static_cast<std::size_t>(m + col) * size;
    row[col] = e_new[col];
    std::fill(row + n, row + size, 0.0);
  }
  const LapResult lap = solve_lap(a, size, size);
  out.feasible = lap.feasible;
  out.cost = lap.cost;
  if (!lap.feasible) return out;
  for (int32_t r = 0; r < m; ++r)
    if (lap.row_to_col[r] < n) out.tuple_index[r] = lap.row_to_col[r];
  for (int32_t col = 0; col < n; ++col)
    if (lap.col_to_row[col] >= m) out.new_tuples.push_back(col);
  return out;
}

int64_t polish_sd(const CostTensorSD& c, std::vector<int32_t>& tuples, const LocalSearchOptions& options) {
  options.validate();
  const int32_t S = c.dims();
  int64_t moves = 0;
  double current = assignment_cost_sd(c, tuples);
  std::vector<int32_t> partial, candidate, t(S);
  std::vector<double> e, e_new;
  for (int pass = 0; pass < options.max_rounds; ++pass) {
    bool improved = false;
    for (int32_t s = 0; s < S; ++s) {
      // Partial tuples without sensor s (those left all-dummy dissolve: their index is free again).
      partial.clear();
      for (std::size_t k = 0; k < tuples.size(); k += S) {
        bool other = false;
        for (int32_t q = 0; q < S; ++q) other |= (q != s && tuples[k + q] >= 0);
        if (!other) continue;
        partial.insert(partial.end(), tuples.begin() + k, tuples.begin() + k + S);
      }
      const int32_t m = static_cast<int32_t>(partial.size() / S), ns = c.n[s];
      e.assign(static_cast<std::size_t>(m) * (ns + 1), 0.0);
      for (int32_t r = 0; r < m; ++r) {
        std::copy(partial.begin() + static_cast<std::ptrdiff_t>(r) * S,
                  partial.begin() + static_cast<std::ptrdiff_t>(r + 1) * S, t.begin());
        for (int32_t i = 0; i <= ns; ++i) {
          t[s] = i < ns ? i : kNoTrack;
          e[static_cast<std::size_t>(r) * (ns + 1) + i] = c.at(t);
        }
      }
      e_new.assign(ns, 0.0);
      std::fill(t.begin(), t.end(), kNoTrack);
      for (int32_t i = 0; i < ns; ++i) {
        t[s] = i;
        e_new[i] = c.at(t);
      }
      const DimensionMatch match = match_dimension(e, e_new, m, ns);
      if (!match.feasible || !(match.cost < current - 1e-9 * std::max(1.0, std::abs(current)))) continue;
      candidate.clear();
      for (int32_t r = 0; r < m; ++r) {
        partial[static_cast<std::size_t>(r) * S + s] = match.tuple_index[r];
        candidate.insert(candidate.end(), partial.begin() + static_cast<std::ptrdiff_t>(r) * S,
                         partial.begin() + static_cast<std::ptrdiff_t>(r + 1) * S);
      }
      for (int32_t i : match.new_tuples) {
        std::fill(t.begin(), t.end(), kNoTrack);
        t[s] = i;
        candidate.insert(candidate.end(), t.begin(), t.end());
      }
      tuples.swap(candidate);
      current = assignment_cost_sd(c, tuples);
      ++moves;
      improved = true;
    }
    if (!improved) break;
  }
  return moves;
}

CostTensorSD to_sd(const CostTensor3& b, double miss_cost) {
  CostTensorSD c({b.n1, b.n2, b.n3});
  const float miss = static_cast<float>(miss_cost);
  std::array<int32_t, 3> t{};
  for (t[0] = 0; t[0] <= b.n1; ++t[0])
    for (t[1] = 0; t[1] <= b.n2; ++t[1])
      for (t[2] = 0; t[2] <= b.n3; ++t[2]) {
        const int missing = (t[0] == b.n1) + (t[1] == b.n2) + (t[2] == b.n3);
        c.at(t) = missing == 0 ? b.at(t[0], t[1], t[2]) : (missing == 3 ? 0.f : missing * miss);
      }
  return c;
}

}  // namespace trackassoc
