// Shared pieces of the `trackassoc` subcommands: the options every command has (--seed,
// --threads), the thread-count scope, and the registration hooks of each command file.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <oneapi/tbb/global_control.h>

namespace trackassoc::cli {

struct CommonOptions {
  uint64_t seed = 1;
  int threads = 0;  // 0 = all hardware threads
};

// Adds --seed and --threads to a subcommand.
inline void add_common_options(CLI::App* cmd, CommonOptions& common) {
  cmd->add_option("--seed", common.seed, "Random seed; results are bit-identical for any --threads")
      ->capture_default_str();
  cmd->add_option("--threads", common.threads, "Worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

// Limits oneTBB to `threads` workers for the lifetime of the object (DESIGN §2, Threads).
class ThreadScope {
 public:
  explicit ThreadScope(int threads) {
    if (threads > 0)
      control_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                       static_cast<std::size_t>(threads));
  }

 private:
  std::unique_ptr<tbb::global_control> control_;
};

// Each command file engine/cli/cmd_*.cpp defines one of these; main.cpp calls them all.

}  // namespace trackassoc::cli
