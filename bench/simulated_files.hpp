// The embedded scenarios' files for the benchmarks, simulated once per program with seed 1 (run 0)
// and kept for its lifetime, so that a case times the association, not the simulation.
#pragma once

#include <map>
#include <string>

#include "engine/simulation/simulation.hpp"
#include "engine/simulation/simulation_io.hpp"
#include "io/track_file.hpp"

namespace trackassoc::bench {

inline const TrackFile& simulated_track_file(const std::string& scenario) {
  static std::map<std::string, TrackFile> files;
  auto it = files.find(scenario);
  if (it != files.end()) return it->second;
  const Scenario sc = load_scenario(scenario);
  return files.emplace(scenario, simulation_to_track_file(sc, simulate(sc, 1, 0))).first->second;
}

}  // namespace trackassoc::bench
