#include "engine/pipeline/stage_report.hpp"

#include <sys/resource.h>

#include <utility>

#include "kernels/core/stopwatch.hpp"

namespace trackassoc {

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

StageReport stage_since(std::string name, std::chrono::steady_clock::time_point t0, double data_mib) {
  const double seconds = seconds_since(t0);
  return {std::move(name), seconds, peak_rss_mib(), data_mib};
}

double total_seconds(std::span<const StageReport> stages) {
  double t = 0.0;
  for (const StageReport& st : stages) t += st.seconds;
  return t;
}

}  // namespace trackassoc
