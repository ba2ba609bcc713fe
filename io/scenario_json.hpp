// Scenario JSON (DESIGN §3): read, validate and write trackassoc::Scenario.
// Every field has a default, so a scenario file only states what differs. Unknown keys are an
// error (a misspelt key must not silently fall back to a default).
#pragma once

#include <string>

#include "kernels/scenario.hpp"

namespace trackassoc {

// `source` names the file (or "<string>") in error messages.
Scenario parse_scenario_json(const std::string& text, const std::string& source = "<string>");
Scenario read_scenario_file(const std::string& path);
std::string scenario_to_json(const Scenario& scenario);  // pretty-printed, round-trips exactly

}  // namespace trackassoc
