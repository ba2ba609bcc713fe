// Hand-made packet streams for the fuzzy association tests and benchmark (no simulation needed):
// constant-velocity targets seen by 4 sensors with period 4 s and offsets 0, 1, 2, 3 s (the seed 001
// timing), plots with Cartesian Gaussian errors σ = 50, 100, 50, 120 m per axis, reliabilities
// 1.0, 0.8, 1.0, 0.6. Local track l of sensor s is target l; its dense index is s·targets + l.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/core/random.hpp"
#include "kernels/fuzzy/fuzzy_association.hpp"

namespace trackassoc::test_scenes {

struct Scene {
  std::vector<int32_t> sensor, local, target;
  std::vector<double> t, x, y;
  std::vector<double> reliability{1.0, 0.8, 1.0, 0.6};
  std::size_t num_local = 0;
  std::size_t size() const { return t.size(); }
  PacketSpans spans() const { return {sensor, local, t, x, y}; }
};

// targets: (x, y, vx, vy) at t = 0.
inline Scene make_scene(uint64_t seed, int run, const std::vector<std::array<double, 4>>& targets,
                        double duration, double period = 4.0) {
  Scene s;
  const double sigma[4] = {50.0, 100.0, 50.0, 120.0};
  const int nt = static_cast<int>(targets.size());
  s.num_local = 4 * targets.size();
  for (int sensor = 0; sensor < 4; ++sensor) {
    CounterRng rng(seed, static_cast<uint64_t>(run), static_cast<uint64_t>(sensor));
    for (double t = sensor * period / 4.0; t <= duration; t += period) {
      for (int k = 0; k < nt; ++k) {
        const auto& g = targets[k];
        s.sensor.push_back(sensor);
        s.local.push_back(sensor * nt + k);
        s.target.push_back(k);
        s.t.push_back(t);
        s.x.push_back(g[0] + g[2] * t + rng.normal(0.0, sigma[sensor]));
        s.y.push_back(g[1] + g[3] * t + rng.normal(0.0, sigma[sensor]));
      }
    }
  }
  return s;
}

}  // namespace trackassoc::test_scenes
