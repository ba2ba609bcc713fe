// Elapsed wall time for the Summary structs' wall_time_s and the stage reports (docs/design.md §2).
#pragma once

#include <chrono>

namespace trackassoc {

// Seconds of steady (monotonic) clock since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace trackassoc
