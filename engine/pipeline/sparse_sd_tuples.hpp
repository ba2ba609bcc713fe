// A component too large for its dense sub-tensor, solved over its allowed tuples (docs/design.md
// §4.10, "giant components, certified"; issue 31 item 4).
//
// The dense sub-tensor of a component has Π(n_s + 1) entries; a giant component (long-range radars,
// wide cross-range errors: 3 × 30 000 tracks of recorded_10k at three times its density) has far
// more than any memory, yet few of them are allowed: a tuple is allowed only when its members are
// connected through gated-in pairs and no two coexisting members failed the gate (the rule of
// engine/pipeline/tuple_cost.hpp). So the allowed tuples are listed, and the S-D assignment over
// the list is solved by the Lagrangian relaxation of kernels/assignment/sd/lagrangian_sd_tuples.hpp,
// which reports a lower bound and so the component's duality gap.
//
// Listing: every track's singleton, then, breadth first, every listed tuple grown by one gated
// neighbour (on another sensor, with no failed pair to any member): a connected set grows from any
// of its members along a spanning tree, so every allowed tuple is listed, each once (a hash set over
// the per-sensor indices). Memory: O(T·S) for T allowed tuples, checked against --memory-budget
// as the list grows (the budget shared by the components listed at once). The list suits
// components in which few sensors see each target (T ≈ 4 per track on recorded_10k at three times
// its density); where many sensors all gate one another a target has up to 2^S allowed subsets
// (25 radars: 3·10⁷), so a list longer than kMaxListedTuplesPerTrack per track is abandoned too.
// An abandoned list sends the component to sequential LAP merging
// (engine/pipeline/sparse_sd_components.hpp), reported as the fallback.
// Complexity: O(T·k·deg·k²) to list (k members, deg gated neighbours per member), then the
// relaxation's O(T·S + T log T) per iteration.
#pragma once

#include <cstddef>
#include <optional>

#include "engine/pipeline/sparse_sd_components.hpp"
#include "kernels/assignment/sd/lagrangian_sd_tuples.hpp"

namespace trackassoc {

inline constexpr double kMaxListedTuplesPerTrack = 32.0;
// A component whose dense sub-tensor fits is still solved over its list when the tensor has more
// than kListAboveEntries entries and at least kTensorPerListedTuple per listed tuple
// (engine/pipeline/sparse_sd_components.cpp): widearea_small's 16-radar components.
inline constexpr double kListAboveEntries = 65536.0;
inline constexpr double kTensorPerListedTuple = 64.0;

// The allowed tuples of a component (indices are the view's per-sensor indices, costs by
// sd_component_tuple_cost), or nullopt when the list would need more than `max_bytes` or hold more
// than kMaxListedTuplesPerTrack tuples per track.
std::optional<TupleListSD> list_component_tuples(const SDComponentView& v, bool all_pairs, double max_bytes);

// The component solved over `list` by the relaxation (default options: 300 iterations, stop at a
// 10⁻³ relative gap): tuples, costs, objective and lower bound; listed_tuples = list.size().
SDComponentResult solve_sd_component_by_tuples(const SDComponentView& v, const TupleListSD& list,
                                               bool all_pairs, const LagrangianOptions& options = {});

}  // namespace trackassoc
