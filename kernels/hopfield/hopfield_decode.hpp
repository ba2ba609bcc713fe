// Decoding a Hopfield state into a valid 3-D assignment, and repair (docs/design.md §4.4 "Decoding and
// repair").
//
// A network state is "raw valid" when it is itself an assignment: min(n1, n2, n3) active neurons,
// no two in one plane. Otherwise it is repaired:
//   greedy  take the candidate neurons in priority order (active neurons by cost, or continuous
//           outputs by V), keep each one whose three indices are still free, then complete the
//           free indices with the cheapest free tuple first. O(F log F) for F free tuples.
//   lap     keep the conflict-free active tuples as above, then complete the free indices by
//           sequential pairwise LAPs on the free sub-tensor (c12(i,j) = min_k b_ijk, then the
//           pairs against k), Jonker–Volgenant (kernels/assignment/lap.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/core/enum_names.hpp"

namespace trackassoc {

enum class HopfieldRepair { kGreedy, kLap };
inline constexpr EnumName<HopfieldRepair> kHopfieldRepairNames[]{{HopfieldRepair::kGreedy, "greedy"},
                                                                 {HopfieldRepair::kLap, "lap"}};
constexpr std::span<const EnumName<HopfieldRepair>> enum_names(HopfieldRepair) {
  return kHopfieldRepairNames;
}

// True when the 0/1 state (standard layout) is a valid assignment.
bool is_valid_state(std::span<const uint8_t> V, int32_t n1, int32_t n2, int32_t n3);

// Active neurons of a 0/1 state in ascending cost order.
std::vector<uint32_t> active_by_cost(std::span<const uint8_t> V, const CostTensor3& cost);
// Neurons with V > threshold in descending V order (continuous decoding).
std::vector<uint32_t> active_by_output(std::span<const float> V, float threshold);

// Keeps `priority` neurons whose indices are free, then completes as `method` says. Always
// returns a valid assignment of min(n1, n2, n3) complete tuples (ignores miss_cost).
std::vector<Tuple3> repair_assignment(const CostTensor3& cost, std::span<const uint32_t> priority,
                                      HopfieldRepair method);

}  // namespace trackassoc
