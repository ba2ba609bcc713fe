// The partition stage (docs/design.md §1 and §4.3, "Sparse form"): the problem split into
// independent subproblems for the component solver.
//
//   * the whole problem (the dense paths, pipeline.hpp and pipeline_sd.hpp): one component, the
//     full tensor;
//   * connected components of the gated pair graph (the sparse paths): nodes are the front end's
//     local tracks (AlignedSensors::offset), edges the gated-in pairs of the pair source
//     (engine/pipeline/pair_source.hpp). A tuple that the costs allow is connected through gated-in
//     pairs, so it lies in one component (kernels/assignment/clusters.hpp); O(E·α(N)).
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>

#include "engine/pipeline/front_end.hpp"
#include "io/track_file.hpp"
#include "kernels/assignment/clusters.hpp"
#include "kernels/statistics/sparse_candidates.hpp"

namespace trackassoc {

// The gated pairs of sensor positions a and b (pairs.a index sensor a's tracks).
struct GatedPairs {
  int32_t a = 0, b = 0;
  const SparsePairStatistic* pairs = nullptr;
};

// Connected components over the nodes of `sensors` with an edge per gated pair.
Components gated_pair_components(const AlignedSensors& sensors, std::span<const GatedPairs> gated);

// The component solves' results summed once, for every partitioned path: Σ objectives, Σ
// Lagrangian lower bounds (unknown when a component has none: a heuristic, the merging fallback),
// the largest per-component relative gap (objective − bound)/max(|objective|, 1e-9) and the
// components above 1 %, and one termination: the components' own when they all agree, else each
// with its count, "gap_tolerance:3,optimal:140" (names of kernels/assignment/assignment_types.hpp).
struct ComponentTotals {
  int64_t solved = 0;
  double objective = 0.0, lower_bound = 0.0;
  bool bound_known = true;
  double largest_gap = 0.0;
  int64_t above_1pct_gap = 0;
  std::map<std::string, int64_t> terminations;

  void add(double objective, double lower_bound, const std::string& termination);
  std::string termination() const;
  // rec.objective, rec.termination, and rec.lower_bound and rec.gap (as set_bound_and_gap: the gap
  // of the sums, ≥ 0) when every solved component had a bound (NaN otherwise, and with none solved).
  void write_to(AssociationRecord& rec) const;
};

}  // namespace trackassoc
