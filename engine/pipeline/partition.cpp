// The partition stage; see engine/pipeline/partition.hpp.
#include "engine/pipeline/partition.hpp"

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

}  // namespace trackassoc
