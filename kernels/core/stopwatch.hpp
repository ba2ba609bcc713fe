// Elapsed wall time for the Summary structs' wall_time_s and the stage reports (docs/design.md §2).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace trackassoc {

// Seconds of steady (monotonic) clock since t0.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Wall times of consecutive phases: lap(name) closes the phase that started at the last lap (or at
// construction); text() lists them, "read 1.23 s, write 0.45 s".
class PhaseClock {
 public:
  void lap(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.2f s", text_.empty() ? "" : ", ", name,
                  std::chrono::duration<double>(now - t_).count());
    text_ += buf;
    t_ = now;
  }
  const std::string& text() const { return text_; }

 private:
  std::chrono::steady_clock::time_point t_ = std::chrono::steady_clock::now();
  std::string text_;
};

}  // namespace trackassoc
