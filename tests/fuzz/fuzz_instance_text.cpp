// libFuzzer target: parse_3dap_instance on arbitrary bytes. InputError is the expected outcome
// for malformed text; anything else (a crash, a sanitizer report, another exception, a hang) is a bug.
// Build and run: scripts/fuzz.sh (seed corpus tests/fuzz/corpus/fuzz_instance_text/).
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/instance_text.hpp"
#include "kernels/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // A small element budget keeps each run fast; the size checks are exercised all the same.
    const trackassoc::CostTensor3 b = trackassoc::parse_3dap_instance(text, "<fuzz>", std::size_t{1} << 20);
    if (b.size() != static_cast<std::size_t>(b.n1) * b.n2 * b.n3) __builtin_trap();
  } catch (const trackassoc::InputError&) {
  }
  return 0;
}
