#include "io/memory_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>

#include "kernels/core/error.hpp"

namespace trackassoc {
namespace {

std::atomic<std::size_t> g_budget{0};  // 0 = not set: the default
std::atomic<bool> g_was_set{false};
std::atomic<std::size_t> g_baseline{0};  // resident set when the budget was set (or first asked)
std::atomic<bool> g_has_baseline{false};
std::mutex g_baseline_mutex;  // the first work_resident_bytes of several threads: one baseline

// Under AddressSanitizer the resident set holds its shadow memory and its quarantine of freed
// blocks (up to 256 MiB), which grow with the work but are not the work's: there the budget counts
// the stages' own counts only (work_resident_bytes() is 0).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kResidentIsTheWorks = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kResidentIsTheWorks = false;
#else
constexpr bool kResidentIsTheWorks = true;
#endif
#else
constexpr bool kResidentIsTheWorks = true;
#endif

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  std::size_t bytes =
      pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
  // A container's limit (cgroup v2) is the memory this process can really have.
  std::ifstream in("/sys/fs/cgroup/memory.max");
  unsigned long long limit = 0;
  if (in >> limit && limit > 0 && (bytes == 0 || limit < bytes)) bytes = static_cast<std::size_t>(limit);
  return bytes;
}

}  // namespace

std::size_t default_memory_budget_bytes() {
  static const std::size_t budget = [] {
    const std::size_t physical = physical_memory_bytes();
    return physical > 0 ? physical / 2 : std::size_t{4} << 30;
  }();
  return budget;
}

std::size_t memory_budget_bytes() {
  const std::size_t b = g_budget.load(std::memory_order_relaxed);
  return b > 0 ? b : default_memory_budget_bytes();
}

void set_memory_budget_bytes(std::size_t bytes) {
  require(bytes > 0, "--memory-budget", "expected a size > 0");
  g_budget.store(bytes, std::memory_order_relaxed);
  g_was_set.store(true, std::memory_order_relaxed);
  const std::lock_guard<std::mutex> lock(g_baseline_mutex);
  g_baseline.store(resident_bytes(), std::memory_order_relaxed);
  g_has_baseline.store(true, std::memory_order_release);
}

bool memory_budget_was_set() { return g_was_set.load(std::memory_order_relaxed); }

std::size_t bytes_of(double count, std::size_t size) {
  const double b = std::max(0.0, count) * static_cast<double>(size);
  if (!(b < static_cast<double>(std::numeric_limits<std::size_t>::max())))
    return std::numeric_limits<std::size_t>::max();
  return static_cast<std::size_t>(b);
}

std::string size_text(std::size_t bytes) {
  char buffer[64];
  const double b = static_cast<double>(bytes);
  if (bytes == std::numeric_limits<std::size_t>::max())
    std::snprintf(buffer, sizeof buffer, "more than 16 EiB");
  else if (b >= 1024.0 * 1024 * 1024 * 1024)
    std::snprintf(buffer, sizeof buffer, "%.3g TiB", b / (1024.0 * 1024 * 1024 * 1024));
  else if (b >= 1024.0 * 1024 * 1024)
    std::snprintf(buffer, sizeof buffer, "%.3g GiB", b / (1024.0 * 1024 * 1024));
  else if (b >= 1024.0 * 1024)
    std::snprintf(buffer, sizeof buffer, "%.3g MiB", b / (1024.0 * 1024));
  else if (b >= 1024.0)
    std::snprintf(buffer, sizeof buffer, "%.3g KiB", b / 1024.0);
  else
    std::snprintf(buffer, sizeof buffer, "%zu bytes", bytes);
  return buffer;
}

void require_memory(std::size_t bytes, const std::string& what) {
  const std::size_t budget = memory_budget_bytes();
  if (bytes <= budget) return;
  throw InputError(what + " needs " + size_text(bytes) + ", more than the memory budget of " +
                   size_text(budget) + (memory_budget_was_set() ? "" : " (half of the physical memory)") +
                   "; raise it with --memory-budget MIB if the machine has the memory");
}

std::size_t resident_bytes() {
  std::ifstream in("/proc/self/statm");
  unsigned long long size = 0, resident = 0;
  if (!(in >> size >> resident)) return 0;
  const long page = ::sysconf(_SC_PAGESIZE);
  return page > 0 ? static_cast<std::size_t>(resident) * static_cast<std::size_t>(page) : 0;
}

bool address_sanitizer_build() { return !kResidentIsTheWorks; }

std::size_t work_resident_bytes() {
  if (!kResidentIsTheWorks) return 0;
  if (!g_has_baseline.load(std::memory_order_acquire)) {
    const std::lock_guard<std::mutex> lock(g_baseline_mutex);
    if (!g_has_baseline.load(std::memory_order_relaxed)) {
      g_baseline.store(resident_bytes(), std::memory_order_relaxed);
      g_has_baseline.store(true, std::memory_order_release);
    }
  }
  const std::size_t now = resident_bytes(), base = g_baseline.load(std::memory_order_relaxed);
  return now > base ? now - base : 0;
}

double held_or_resident(double held) { return std::max(held, static_cast<double>(work_resident_bytes())); }

void require_memory_beside_held(double held, double bytes, const std::string& what) {
  require_memory_beside(held_or_resident(held), bytes, what);
}

void require_memory_beside(double held, double bytes, const std::string& what) {
  const double now = held;
  const std::size_t budget = memory_budget_bytes();
  if (bytes_of(now + bytes, 1) <= budget) return;
  throw InputError(what + " needs " + size_text(bytes_of(bytes, 1)) + " beside the " +
                   size_text(bytes_of(now, 1)) +
                   " held (the input and the stages before), more than the memory budget of " +
                   size_text(budget) + (memory_budget_was_set() ? "" : " (half of the physical memory)") +
                   "; raise it with --memory-budget MIB if the machine has the memory");
}

}  // namespace trackassoc
