// libFuzzer target: parse_3dap_instance on arbitrary bytes. InputError is the expected outcome
// for malformed text; anything else (a crash, a sanitizer report, another exception, a hang) is a bug.
// Build (the io library itself must carry the coverage instrumentation, hence the global flags):
//   cmake -S . -B build-fuzz -G Ninja -DTRACKASSOC_BUILD_FUZZ=ON -DTRACKASSOC_BUILD_TESTS=OFF
//         -DTRACKASSOC_BUILD_BENCH=OFF -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
//         -DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link,address,undefined
//         -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined
//   cmake --build build-fuzz --target fuzz_instance_text fuzz_track_file
// Run:   build-fuzz/fuzz_instance_text -max_total_time=60 data/3dap
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/instance_text.hpp"
#include "kernels/error.hpp"

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
