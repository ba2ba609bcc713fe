// The S-D assignment with a dummy index, for S ≥ 2 sensors (docs/design.md §4.3; Deb, Yeddanapudi,
// Pattipati, Bar-Shalom, "A generalized S-D assignment algorithm for multisensor-multitarget state
// estimation", IEEE TAES 33(2) 1997; Poore & Rijavec, SIAM J. Optim. 3(3) 1993; MATLAB `assignsd`).
//
// Problem. Sensor s reports n_s local tracks, indexed 0 … n_s−1; index n_s is the dummy, "no track
// from sensor s". A tuple (i_1, …, i_S) with at least one real index is a hypothesis "these tracks
// are one target"; it costs c(i_1, …, i_S). Choose tuples so that every real index of every sensor
// is in exactly one chosen tuple (the dummy may be used any number of times):
//
//   min Σ_t c_t x_t   s.t.  Σ_{t : t_s = i} x_t = 1  for every sensor s and real index i,  x ∈ {0,1}.
//
// A track that matches nothing ends in a tuple of its own (all other indices dummy), so the problem
// is always feasible when those singleton costs are finite. Unequal counts, missed detections and
// targets seen by only some sensors need no special case. For S = 3 with infinite dummy costs it is
// the axial 3-D assignment of assignment_types.hpp.
//
// This header holds the shared pieces: the dense tensor, solutions, validation, the dimension
// re-assignment LAP that feasible recovery and local search are built on, local search, and an
// exact depth-first branch and bound for small instances. kernels/assignment/sd/lagrangian_sd.hpp relaxes it.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/assignment/local_search.hpp"

namespace trackassoc {

// Dense cost over Π (n_s + 1) entries, row-major (first sensor slowest), float (docs/design.md §2). The
// all-dummy entry is never read. Entries may be +inf (forbidden hypothesis); NaN is rejected by
// validate().
struct CostTensorSD {
  std::vector<int32_t> n;           // real tracks per sensor; S = n.size()
  std::vector<std::size_t> stride;  // stride of sensor s in `cost`
  std::vector<float> cost;

  CostTensorSD() = default;
  // Throws InputError when S < 2, a size is negative, or the tensor would exceed `max_entries`.
  explicit CostTensorSD(std::vector<int32_t> sizes, float fill = 0.f,
                        std::size_t max_entries = std::size_t{1} << 29);
  int32_t dims() const { return static_cast<int32_t>(n.size()); }
  // Entry offset of a tuple; kNoTrack (or n_s) selects the dummy of sensor s.
  std::size_t offset(std::span<const int32_t> t) const {
    std::size_t o = 0;
    for (std::size_t s = 0; s < n.size(); ++s)
      o += static_cast<std::size_t>(t[s] < 0 ? n[s] : t[s]) * stride[s];
    return o;
  }
  float at(std::span<const int32_t> t) const { return cost[offset(t)]; }
  float& at(std::span<const int32_t> t) { return cost[offset(t)]; }
  void validate() const;  // sizes consistent, no NaN
};

// Tuples of an S-D solution, K×S row-major, kNoTrack for the dummy.
struct SolutionSD {
  int32_t S = 0;
  std::vector<int32_t> tuples;
  SolverSummary summary;
  std::size_t num_tuples() const { return S ? tuples.size() / S : 0; }
};

// Σ of the chosen tuples' costs (double accumulation).
double assignment_cost_sd(const CostTensorSD& c, std::span<const int32_t> tuples);

// True when every real index of every sensor is in exactly one tuple, no tuple is all-dummy and no
// chosen cost is infinite.
bool is_valid_assignment_sd(const CostTensorSD& c, std::span<const int32_t> tuples);

// Fills objective, lower_bound, gap, abs_gap and feasible from the tuples and a bound.
void finish_summary_sd(const CostTensorSD& c, std::span<const int32_t> tuples, double lower_bound,
                       SolverSummary& summary);

// Matches m partial tuples to the n real indices of one sensor by a LAP with dummies: tuple r takes
// index c at cost e[r·(n+1) + c] or no index at e[r·(n+1) + n]; an index no tuple takes starts a new
// tuple at cost e_new[c]. Solved as one (m+n)×(n+m) LAP (Jonker–Volgenant, kernels/assignment/lap.hpp).
struct DimensionMatch {
  std::vector<int32_t> tuple_index;  // per tuple: its index, or kNoTrack
  std::vector<int32_t> new_tuples;   // indices that start a tuple of their own
  double cost = 0.0;
  bool feasible = true;
};
DimensionMatch match_dimension(std::span<const double> e, std::span<const double> e_new, int32_t m,
                               int32_t n);

// Local search (the S-D form of "fix two dimensions and re-solve the third"): for each sensor s in
// turn, take s out of every tuple and re-assign its indices to the remaining partial tuples by
// match_dimension on the exact costs; a pass over all sensors repeats until none improves. Each move
// is optimal given the others, so the cost never rises. O(passes · S · (K+n)³).
// options.max_rounds bounds the passes. Returns the number of improving moves; `tuples` must be
// valid and stays valid.
int64_t polish_sd(const CostTensorSD& c, std::vector<int32_t>& tuples,
                  const LocalSearchOptions& options = {});

// Exact depth-first branch and bound. A node branches on the lowest free index of the first sensor
// with a free index, over every tuple that holds it together with free indices or dummies of the
// later sensors, cheapest first. Bound: each tuple's cost is shared equally by its real members, so
// Σ over free indices of their cheapest share is a lower bound on completing the node. The
// incumbent starts from `incumbent` (e.g. lr+ls) when given. Exponential in the worst case: meant
// as ground truth for small instances; stops at the time or node limit with termination time_limit
// and the best assignment found (then not proven optimal).
struct ExactSDOptions {
  double time_limit_s = 10.0;
  int64_t max_nodes = 200'000'000;
  void validate() const;
};
SolutionSD solve_exact_sd(const CostTensorSD& c, const ExactSDOptions& options = {},
                          const std::vector<int32_t>* incumbent = nullptr);

// The S-D form of a 3-D tensor: complete tuples copy b_ijk; a tuple with d dummies costs
// d·miss_cost (as in assignment_types.hpp; +inf forbids them). Used to check the S-D solvers
// against the 3-D ones and the known optima.
CostTensorSD to_sd(const CostTensor3& b, double miss_cost);

}  // namespace trackassoc
