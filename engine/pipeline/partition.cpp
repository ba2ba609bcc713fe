// The partition stage; see engine/pipeline/partition.hpp.
#include "engine/pipeline/partition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace trackassoc {

Components gated_pair_components(const AlignedSensors& sensors, std::span<const GatedPairs> gated) {
  std::size_t edges = 0;
  for (const GatedPairs& g : gated) edges += g.pairs->size();
  std::vector<int32_t> u, v;
  u.reserve(edges);
  v.reserve(edges);
  for (const GatedPairs& g : gated)
    for (std::size_t e = 0; e < g.pairs->size(); ++e) {
      u.push_back(sensors.offset[g.a] + g.pairs->a[e]);
      v.push_back(sensors.offset[g.b] + g.pairs->b[e]);
    }
  return connected_components(sensors.nodes(), u, v);
}

void ComponentTotals::add(double component_objective, double component_bound, const std::string& term) {
  ++solved;
  objective += component_objective;
  ++terminations[term];
  if (!std::isfinite(component_bound)) {
    bound_known = false;
    return;
  }
  lower_bound += component_bound;
  const double gap = (component_objective - component_bound) / std::max(std::abs(component_objective), 1e-9);
  largest_gap = std::max(largest_gap, gap);
  above_1pct_gap += gap > 0.01;
}

std::string ComponentTotals::termination() const {
  if (terminations.size() == 1) return terminations.begin()->first;
  std::string out;
  for (const auto& [name, count] : terminations)
    out += (out.empty() ? "" : ",") + name + ":" + std::to_string(count);
  return out;
}

void ComponentTotals::write_to(AssociationRecord& rec) const {
  rec.objective = objective;
  rec.termination = termination();
  rec.lower_bound = rec.gap = std::numeric_limits<double>::quiet_NaN();
  if (!bound_known || solved == 0) return;
  rec.lower_bound = lower_bound;
  rec.gap = std::max(0.0, objective - lower_bound) / std::max(std::abs(objective), 1e-9);
}

}  // namespace trackassoc
