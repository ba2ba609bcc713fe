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
#include <span>

#include "engine/pipeline/front_end.hpp"
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

}  // namespace trackassoc
