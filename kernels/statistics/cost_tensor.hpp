// The 3-D assignment cost tensor (seed 000 Eq. 3; docs/design.md §4.3).
//
//   chain form (as in the paper):  b_ijk = λ_ij + λ_jk
//   all-pairs form:                b_ijk = λ_ij + λ_jk + λ_ik
//
// A pair outside its gate contributes `gated_pair_cost` instead of its λ, so that gated tuples
// stay finite (solvers and the Hopfield normalisation need finite costs) but are never preferred.
// Dense, float, one TBB task per block of i-slices; O(n1·n2·n3) time and memory. A tensor larger
// than `memory_budget_bytes` is refused with an InputError that points to the sparse form.
#pragma once

#include <cstddef>

#include "kernels/assignment/assignment_types.hpp"
#include "kernels/statistics/association_statistic.hpp"

namespace trackassoc {

enum class CostForm { kChain, kAllPairs };
inline constexpr EnumName<CostForm> kCostFormNames[]{{CostForm::kChain, "chain"},
                                                     {CostForm::kAllPairs, "all-pairs"}};
constexpr std::span<const EnumName<CostForm>> enum_names(CostForm) { return kCostFormNames; }

struct CostTensorOptions {
  CostForm form = CostForm::kChain;  // the pipelines default to all-pairs (engine/pipeline/pipeline.hpp)
  std::size_t memory_budget_bytes = std::size_t{2} << 30;  // 2 GiB
  // Substituted for λ of a gated pair. 0 means: 10 × the largest in-gate λ of the three matrices
  // (at least 1e3), computed per tensor.
  double gated_pair_cost = 0.0;
  void validate() const;
};

// λ_ij from `s12` (sensor 1 vs 2), λ_jk from `s23`, λ_ik from `s13` (all-pairs form only; may be
// null for the chain form). Throws InputError when the tensor exceeds the memory budget.
CostTensor3 build_cost_tensor(const PairStatistic& s12, const PairStatistic& s23, const PairStatistic* s13,
                              const CostTensorOptions& options);

// The same, writing into `out` and reusing its storage when it already has the right size (a
// Monte Carlo loop builds one tensor per run; a fresh allocation costs a zero-fill and page faults
// that double the memory traffic of this write-bound kernel).
void build_cost_tensor_into(const PairStatistic& s12, const PairStatistic& s23, const PairStatistic* s13,
                            const CostTensorOptions& options, CostTensor3& out);

}  // namespace trackassoc
