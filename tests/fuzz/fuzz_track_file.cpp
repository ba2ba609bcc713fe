// libFuzzer target: read_track_file on arbitrary bytes written to a temporary file. InputError is
// the expected outcome; a crash, a sanitizer report or another exception in our code is a bug.
//
// The reader is called as the CLI calls it, guarded (io/isolated_run.hpp): libhdf5 1.10 itself
// hangs, overlaps memcpys and overruns buffers on some damaged files (tests/fuzz/regressions/),
// which we cannot fix and which the guard turns into an InputError. The guard's child reads the
// file first; only when it finished does the parent read it in process, where libFuzzer sees the
// coverage. ASan watches our code in both: a report in the child whose faulting frame is in
// libhdf5 (an intercepted memcpy, a SEGV) is the library's known kind of bug, and the child leaves
// with status 5; any other report in the child (status 1, the report on stderr) fails the run,
// as does a report in the parent. A child that hangs is ended by the 2 s limit.
// Build and run: scripts/fuzz.sh (seed corpus tests/fuzz/corpus/fuzz_track_file/).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/memory_budget.hpp"
#include "io/track_file.hpp"
#include "kernels/core/error.hpp"

extern "C" void __asan_set_error_report_callback(void (*callback)(const char*));

namespace {

pid_t g_fuzzer_pid = 0;

// In the reader child: leave with status 5 when the first frame of the report outside the
// sanitizer's interceptors is in libhdf5.
void on_asan_report(const char* report) {
  if (::getpid() == g_fuzzer_pid) return;
  const std::string text(report);
  for (std::size_t at = text.find("    #"); at != std::string::npos; at = text.find("    #", at + 1)) {
    const std::string frame = text.substr(at, text.find('\n', at) - at);
    if (frame.find("__interceptor_") != std::string::npos || frame.find("__asan") != std::string::npos ||
        frame.find("__sanitizer") != std::string::npos)
      continue;
    if (frame.find("libhdf5") != std::string::npos) ::_exit(5);
    return;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  g_fuzzer_pid = ::getpid();
  __asan_set_error_report_callback(on_asan_report);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/trackassoc_fuzz_track_file_" + std::to_string(::getpid()) + ".h5";
  // Each run stays far below -rss_limit_mb; larger declared sizes are refused by the budget. The
  // budget counts the resident set above its baseline (io/memory_budget.hpp), set again at each
  // run: the fuzzer's own memory (its corpus, ASan's quarantine) grows over the runs and is not
  // the reader's, so a fixed baseline would end by refusing every input.
  trackassoc::set_memory_budget_bytes(std::size_t{256} << 20);
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  try {
    trackassoc::read_track_file(path, 2.0);
  } catch (const trackassoc::InputError& e) {
    if (std::string(e.what()).find("failed reading it (exit status 1)") != std::string::npos)
      __builtin_trap();
  }
  return 0;
}
