// Scenarios compiled into the binary from data/scenarios/*.json (see CMakeLists.txt), so that
// `trackassoc run` needs no data files at run time.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace trackassoc {

struct EmbeddedScenario {
  const char* name;  // file name without .json, e.g. "seed000"
  const char* json;
};

const std::vector<EmbeddedScenario>& embedded_scenarios();

// The JSON text of the embedded scenario `name`, or nullopt.
inline std::optional<std::string> embedded_scenario(const std::string& name) {
  for (const auto& s : embedded_scenarios())
    if (name == s.name) return std::string(s.json);
  return std::nullopt;
}

}  // namespace trackassoc
