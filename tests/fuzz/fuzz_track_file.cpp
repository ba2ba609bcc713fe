// libFuzzer target: read_track_file on arbitrary bytes written to a temporary file. InputError is
// the expected outcome; a crash, a sanitizer report or another exception is a bug (ours, or in
// libhdf5 itself, which is not instrumented: see the report in notes).
// Build: as tests/fuzz/fuzz_instance_text.cpp (with -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,...).
// Run:   build-fuzz/fuzz_track_file -max_total_time=60 -rss_limit_mb=4096 CORPUS_DIR
// A seed corpus: any file written by `trackassoc simulate`, or the files of tests/test_io_track_file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/track_file.hpp"
#include "kernels/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/trackassoc_fuzz_track_file_" + std::to_string(::getpid()) + ".h5";
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  try {
    // In process: the guarded read_track_file forks, which would hide the reader from the fuzzer.
    trackassoc::read_track_file_in_process(path);
  } catch (const trackassoc::InputError&) {
  }
  return 0;
}
