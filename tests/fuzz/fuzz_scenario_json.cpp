// libFuzzer target: parse_scenario_json on arbitrary bytes (io/scenario_json.hpp, through
// io/json_input.hpp). InputError is the expected outcome for a malformed scenario; a crash, a
// sanitizer report, another exception or a hang is a bug. A scenario that parses must survive the
// round trip scenario_to_json -> parse_scenario_json unchanged.
// Build and run: scripts/fuzz.sh (seed corpus tests/fuzz/corpus/fuzz_scenario_json/).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/scenario_json.hpp"
#include "kernels/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  trackassoc::Scenario s;
  try {
    s = trackassoc::parse_scenario_json(text, "<fuzz>");
  } catch (const trackassoc::InputError&) {
    return 0;
  }
  try {
    if (!(trackassoc::parse_scenario_json(trackassoc::scenario_to_json(s), "<round trip>") == s))
      __builtin_trap();
  } catch (const trackassoc::InputError&) {
    __builtin_trap();  // what was read must be writable and readable again
  }
  return 0;
}
