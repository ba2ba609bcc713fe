#include "kernels/assignment/assignment_canonical.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "kernels/core/error.hpp"

namespace trackassoc {

CanonicalProblem3 make_canonical(const CostTensor3& b, std::size_t max_padded_elements) {
  require(b.n1 >= 0 && b.n2 >= 0 && b.n3 >= 0, "cost tensor", "negative size");
  require(b.cost.size() == static_cast<std::size_t>(b.n1) * b.n2 * b.n3, "cost tensor",
          "has " + std::to_string(b.cost.size()) + " entries, expected n1*n2*n3");
  require(!std::isnan(b.miss_cost) && b.miss_cost > -std::numeric_limits<float>::infinity(), "cost tensor",
          "miss_cost must be a number or +inf");
  bool integer = std::isfinite(b.miss_cost) ? std::nearbyint(b.miss_cost) == b.miss_cost : true;
  for (std::size_t e = 0; e < b.cost.size(); ++e) {
    const float x = b.cost[e];
    if (std::isnan(x) || x == -std::numeric_limits<float>::infinity())
      throw InputError("cost tensor: entry " + std::to_string(e) + " is " + std::to_string(x) +
                       "; expected a finite cost or +inf (forbidden tuple)");
    if (integer && std::isfinite(x) && std::nearbyint(x) != x) integer = false;
  }

  CanonicalProblem3 p;
  p.original_n = {b.n1, b.n2, b.n3};
  p.integer_costs = integer;
  p.padded = std::isfinite(b.miss_cost);

  if (p.padded) {
    const std::size_t m = static_cast<std::size_t>(b.n1) + b.n2 + b.n3;
    require(m * m * m <= max_padded_elements, "cost tensor",
            "finite miss_cost pads each dimension to n1+n2+n3 = " + std::to_string(m) + ", " +
                std::to_string(m * m * m) + " entries, above the limit of " +
                std::to_string(max_padded_elements) +
                "; use miss_cost = inf (min(n1,n2,n3) complete tuples) or a smaller problem");
    const int32_t M = static_cast<int32_t>(m);
    p.original_dim = {0, 1, 2};
    p.tensor = CostTensor3(M, M, M);
    for (int32_t i = 0; i < M; ++i)
      for (int32_t j = 0; j < M; ++j)
        for (int32_t k = 0; k < M; ++k) {
          const int q = (i >= b.n1) + (j >= b.n2) + (k >= b.n3);
          p.tensor.at(i, j, k) =
              q == 0 ? b.at(i, j, k) : (q == 3 ? 0.f : static_cast<float>(q) * b.miss_cost);
        }
    return p;
  }

  // Sort the dimensions by size (stable, so equal sizes keep their order) and permute the tensor.
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return p.original_n[x] < p.original_n[y]; });
  p.original_dim = order;
  if (order == std::array<int, 3>{0, 1, 2}) {
    p.tensor = b;
    p.tensor.miss_cost = std::numeric_limits<float>::infinity();
    return p;
  }
  const std::array<int32_t, 3> n = p.original_n;
  p.tensor = CostTensor3(n[order[0]], n[order[1]], n[order[2]]);
  std::array<int32_t, 3> orig{};
  for (int32_t a = 0; a < p.tensor.n1; ++a)
    for (int32_t c = 0; c < p.tensor.n2; ++c)
      for (int32_t d = 0; d < p.tensor.n3; ++d) {
        orig[order[0]] = a;
        orig[order[1]] = c;
        orig[order[2]] = d;
        p.tensor.at(a, c, d) = b.at(orig[0], orig[1], orig[2]);
      }
  return p;
}

std::vector<Tuple3> to_original(const CanonicalProblem3& p, const std::vector<Tuple3>& canonical) {
  std::vector<Tuple3> out;
  out.reserve(canonical.size());
  for (const Tuple3& t : canonical) {
    Tuple3 o{};
    for (int d = 0; d < 3; ++d) o[p.original_dim[d]] = t[d];
    if (p.padded) {
      int q = 0;
      for (int d = 0; d < 3; ++d)
        if (o[d] >= p.original_n[d]) {
          o[d] = kNoTrack;
          ++q;
        }
      if (q == 3) continue;
    }
    out.push_back(o);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void finish_summary(const CostTensor3& original, const std::vector<Tuple3>& tuples, double lower_bound,
                    SolverSummary& summary) {
  summary.feasible = is_valid_assignment(original, tuples);
  // With miss_cost = inf, is_valid_assignment demands min(n) complete tuples; a tuple of +inf cost
  // (forbidden) makes the assignment infeasible too.
  summary.objective = assignment_cost(original, tuples);
  if (!std::isfinite(summary.objective)) summary.feasible = false;
  set_bound_and_gap(summary, lower_bound);
}

}  // namespace trackassoc
