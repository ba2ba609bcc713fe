// The dense 3-D assignment cost tensor (seed 000 Eq. 3; docs/design.md §4.3). See the header.
//
// Layout of the work: the pair costs are first converted once to float matrices e12 (n1×n2),
// e23 (n2×n3) and e13 (n1×n3) with the gate applied. Then every (i, j) row of the tensor is
//   chain:      b[i, j, :] = e12[i, j] + e23[j, :]
//   all-pairs:  b[i, j, :] = e12[i, j] + e23[j, :] + e13[i, :]
// a unit-stride loop over k that the compiler vectorises; the inputs are O(n²) and stay in cache,
// so the kernel is bound by the write bandwidth of the n³ floats (docs/design.md §6). One TBB task per
// block of i-slices; each element is computed independently, so the result is bit-identical for
// any thread count.
#include "kernels/statistics/cost_tensor.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "kernels/core/error.hpp"
#include "kernels/core/parallel.hpp"

namespace trackassoc {

void CostTensorOptions::validate() const {
  require(memory_budget_bytes > 0, "CostTensorOptions.memory_budget_bytes", "must be positive");
  require(std::isfinite(gated_pair_cost) && gated_pair_cost >= 0.0, "CostTensorOptions.gated_pair_cost",
          "must be finite and >= 0 (0 = automatic), got " + std::to_string(gated_pair_cost));
}

namespace {

// Pair costs above this are clamped so that a sum of three stays finite in float (+inf means
// "forbidden" to the solvers, which an ungated but far-apart pair is not).
constexpr double kMaxPairCost = 1e30;

// Grain for the O(n²) passes over a pair matrix: rows of at least ~8 K entries per task.
std::size_t row_grain(int32_t n_b) { return std::max<std::size_t>(1, 8192 / std::max<int32_t>(n_b, 1)); }

// λ where the pair is in the gate, `otherwise` elsewhere, selected with a bit mask: the gate flags
// are data-dependent, and a branch here mispredicts about half the time on real gates.
inline double gate_select(uint8_t in_gate, double lambda, double otherwise) {
  const uint64_t mask = uint64_t{0} - static_cast<uint64_t>(in_gate != 0);
  return std::bit_cast<double>((std::bit_cast<uint64_t>(lambda) & mask) |
                               (std::bit_cast<uint64_t>(otherwise) & ~mask));
}

// Checks the sizes and that no in-gate λ is NaN; returns the largest finite in-gate λ (0 if none).
// Rows are scanned in parallel; the per-row maxima are reduced serially (max is exact, so the
// result does not depend on the split).
double check_statistic(const PairStatistic& s, const char* name) {
  const std::size_t n = static_cast<std::size_t>(s.n_a) * s.n_b;
  require(
      s.n_a >= 0 && s.n_b >= 0 && s.lambda.size() == n && s.in_gate.size() == n,
      std::string("build_cost_tensor.") + name,
      "pair statistic arrays do not match its size " + std::to_string(s.n_a) + "x" + std::to_string(s.n_b));
  std::vector<double> row_max(s.n_a, 0.0);
  std::vector<uint8_t> row_nan(s.n_a, 0);
  parallel_for_range(s.n_a, row_grain(s.n_b), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t a = lo; a < hi; ++a) {
      const double* l = s.lambda.data() + a * s.n_b;
      const uint8_t* g = s.in_gate.data() + a * s.n_b;
      double m = 0.0;
      bool nan = false;
      for (int32_t b = 0; b < s.n_b; ++b) {
        const double v = gate_select(g[b], l[b], 0.0);
        nan |= v != v;
        m = std::max(m, std::fabs(v) < std::numeric_limits<double>::infinity() ? v : 0.0);
      }
      row_max[a] = m;
      row_nan[a] = nan;
    }
  });
  double m = 0.0;
  for (int32_t a = 0; a < s.n_a; ++a) {
    if (row_nan[a])
      for (int32_t b = 0; b < s.n_b; ++b)
        if (s.in_gate[static_cast<std::size_t>(a) * s.n_b + b] &&
            std::isnan(s.lambda[static_cast<std::size_t>(a) * s.n_b + b]))
          throw InputError(std::string("build_cost_tensor.") + name + ": lambda of pair " +
                           std::to_string(a) + "," + std::to_string(b) + " is in the gate but NaN");
    m = std::max(m, row_max[a]);
  }
  return m;
}

std::vector<float> effective_pair_costs(const PairStatistic& s, double gated) {
  std::vector<float> e(s.lambda.size());
  parallel_for_range(s.n_a, row_grain(s.n_b), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t p = lo * s.n_b; p < hi * s.n_b; ++p)
      e[p] = static_cast<float>(std::min(gate_select(s.in_gate[p], s.lambda[p], gated), kMaxPairCost));
  });
  return e;
}

}  // namespace

void build_cost_tensor_into(const PairStatistic& s12, const PairStatistic& s23, const PairStatistic* s13,
                            const CostTensorOptions& options, CostTensor3& out) {
  options.validate();
  const bool all_pairs = options.form == CostForm::kAllPairs;
  require(!all_pairs || s13 != nullptr, "build_cost_tensor",
          "the all-pairs form needs the sensor 1-3 statistic");
  double max_lambda = std::max(check_statistic(s12, "s12"), check_statistic(s23, "s23"));
  const int32_t n1 = s12.n_a, n2 = s12.n_b, n3 = s23.n_b;
  require(s23.n_a == n2, "build_cost_tensor",
          "s12 has " + std::to_string(n2) + " sensor-2 tracks but s23 has " + std::to_string(s23.n_a));
  if (all_pairs) {
    max_lambda = std::max(max_lambda, check_statistic(*s13, "s13"));
    require(s13->n_a == n1 && s13->n_b == n3, "build_cost_tensor",
            "s13 is " + std::to_string(s13->n_a) + "x" + std::to_string(s13->n_b) + ", expected " +
                std::to_string(n1) + "x" + std::to_string(n3));
  }

  // Memory guard, with overflow-safe arithmetic.
  const std::size_t count = static_cast<std::size_t>(n1) * static_cast<std::size_t>(n2);
  const bool overflow = n3 != 0 && count > std::numeric_limits<std::size_t>::max() / sizeof(float) / n3;
  const std::size_t bytes = overflow ? std::numeric_limits<std::size_t>::max() : count * n3 * sizeof(float);
  if (overflow || bytes > options.memory_budget_bytes)
    throw InputError("build_cost_tensor: the dense " + std::to_string(n1) + "x" + std::to_string(n2) + "x" +
                     std::to_string(n3) + " cost tensor needs " + std::to_string(bytes) + " bytes (" +
                     std::to_string(bytes >> 20) + " MiB), over the memory budget of " +
                     std::to_string(options.memory_budget_bytes) +
                     " bytes (CostTensorOptions.memory_budget_bytes); use the sparse form (gated candidate "
                     "tuples only, docs/design.md §4.3) for track sets this large, or raise the budget");

  double gated = options.gated_pair_cost;
  if (gated == 0.0) gated = std::max(10.0 * max_lambda, 1e3);
  gated = std::min(gated, kMaxPairCost);
  const std::vector<float> e12 = effective_pair_costs(s12, gated);
  const std::vector<float> e23 = effective_pair_costs(s23, gated);
  const std::vector<float> e13 = all_pairs ? effective_pair_costs(*s13, gated) : std::vector<float>{};

  const std::size_t total = count * n3;
  out.n1 = n1;
  out.n2 = n2;
  out.n3 = n3;
  out.miss_cost = std::numeric_limits<float>::infinity();
  if (out.cost.size() != total) {
    out.cost.clear();
    out.cost.shrink_to_fit();
    out.cost.resize(total);
  }
  if (total == 0) return;

  float* const b = out.cost.data();
  const float* const p12 = e12.data();
  const float* const p23 = e23.data();
  const float* const p13 = e13.data();
  // About 64 K floats (256 KiB) per task at least.
  const std::size_t slice = static_cast<std::size_t>(n2) * n3;
  const std::size_t grain =
      std::max<std::size_t>(1, (std::size_t{1} << 16) / std::max<std::size_t>(slice, 1));
  parallel_for_range(static_cast<std::size_t>(n1), grain, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i)
      for (int32_t j = 0; j < n2; ++j) {
        float* __restrict row = b + (i * n2 + j) * n3;
        const float a = p12[i * n2 + j];
        const float* __restrict r23 = p23 + static_cast<std::size_t>(j) * n3;
        if (all_pairs) {
          const float* __restrict r13 = p13 + i * n3;
          for (int32_t k = 0; k < n3; ++k) row[k] = a + r23[k] + r13[k];  // λ_ij + λ_jk + λ_ik
        } else {
          for (int32_t k = 0; k < n3; ++k) row[k] = a + r23[k];  // seed 000 Eq. 3: λ_ij + λ_jk
        }
      }
  });
}

CostTensor3 build_cost_tensor(const PairStatistic& s12, const PairStatistic& s23, const PairStatistic* s13,
                              const CostTensorOptions& options) {
  CostTensor3 out;
  build_cost_tensor_into(s12, s23, s13, options, out);
  return out;
}

}  // namespace trackassoc
