// Shared pieces of the `trackassoc` subcommands: the ranges of numeric options, the options every
// command has (--seed, --threads, --output), the thread-count scope, and the registration hooks of
// each command file. Studies end with engine/cli/study_command.hpp; associate, run and solve3d
// take the flags of engine/cli/association_flags.hpp and engine/cli/hopfield_flags.hpp.
#pragma once

#include <oneapi/tbb/global_control.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "kernels/core/enum_names.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc::cli {

// The range of a numeric option (issue 15). Every numeric option of the CLI declares its range
// with one of these: --help shows it ("in [0, 1)") and CLI11 refuses a value outside it before the
// command runs, as a usage error (exit 2, "--NAME: expected a value in [0, 1), got -0.5"). NaN and
// ±inf lie outside every range; an integer option still refuses "2.5" by CLI11's conversion.
inline CLI::Validator in_range(double lo, double hi, bool lo_open = false, bool hi_open = false) {
  auto text = [](double v) {
    if (std::isinf(v)) return std::string(v > 0 ? "inf" : "-inf");
    std::ostringstream s;
    s << v;
    return s.str();
  };
  const std::string range =
      std::string(lo_open ? "(" : "[") + text(lo) + ", " + text(hi) + (hi_open || std::isinf(hi) ? ")" : "]");
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        double v = 0;
        const bool number = CLI::detail::lexical_cast(input, v) && std::isfinite(v);
        const bool inside = number && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
        return inside ? std::string() : "expected a value in " + range + ", got " + input;
      },
      "in " + range);
}
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline CLI::Validator at_least(double lo) { return in_range(lo, kInf); }     // [lo, inf)
inline CLI::Validator above(double lo) { return in_range(lo, kInf, true); }  // (lo, inf)

// --seed: a decimal integer in [0, 2^64-1]. CLI11 itself reads a uint64_t with strtoull, which
// wraps "-1" to 2^64-1, saturates "1e30"-sized digit strings and reads "010" as octal.
inline CLI::Validator seed_range() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const std::string why = "expected a decimal integer in [0, 18446744073709551615], got " + input;
        if (input.empty() || input.find_first_not_of("0123456789") != std::string::npos) return why;
        errno = 0;
        (void)std::strtoull(input.c_str(), nullptr, 10);
        if (errno == ERANGE) return why;
        input.erase(0, std::min(input.find_first_not_of('0'), input.size() - 1));  // "010" is ten
        return std::string();
      },
      "in [0, 2^64-1]");
}

struct CommonOptions {
  uint64_t seed = 1;
  int threads = 0;  // 0 = all hardware threads
};

// Adds --seed and --threads to a subcommand.
inline void add_common_options(CLI::App* cmd, CommonOptions& common) {
  cmd->add_option("--seed", common.seed, "Random seed; results are bit-identical for any --threads")
      ->transform(seed_range())  // transform: it may rewrite "010" as "10"
      ->capture_default_str();
  cmd->add_option("--threads", common.threads, "Worker threads (0 = all cores)")
      ->check(in_range(0, 1 << 16))
      ->capture_default_str();
}

// Limits oneTBB to `threads` workers for the lifetime of the object (docs/design.md §2, Threads).
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

// CLI11's check that a flag names one enumerator of E, from E's one name table
// (kernels/core/enum_names.hpp), so the flag, its --help and parse_enum<E> cannot drift apart.
template <class E>
CLI::Validator enum_choices() {
  std::vector<std::string> names;
  for (const auto& n : enum_names(E{})) names.emplace_back(n.name);
  return CLI::IsMember(names);
}

// Adds --output,-o, the one name of every command's output file (or folder).
inline CLI::Option* add_output_option(CLI::App* cmd, std::string& output, const std::string& help) {
  return cmd->add_option("--output,-o", output, help);
}

// Each command file engine/cli/cmd_*.cpp defines one of these; main.cpp calls them all.
void register_simulate(CLI::App& app);
void register_associate(CLI::App& app);
void register_evaluate(CLI::App& app);
void register_fuse(CLI::App& app);  // cmd_fuse.cpp
void register_run(CLI::App& app);
void register_dataset(CLI::App& app);        // cmd_siamese.cpp
void register_train_siamese(CLI::App& app);  // cmd_siamese.cpp
void register_solve3d(CLI::App& app);
void register_filter(CLI::App& app);
void register_import(CLI::App& app);   // cmd_import.cpp
void register_solvers(CLI::App& app);  // cmd_solvers.cpp
void register_export(CLI::App& app);   // cmd_import.cpp
void register_experiment(CLI::App& app);
void register_autoferry(CLI::App& app);  // cmd_autoferry.cpp: import autoferry, experiment autoferry
// Sub-subcommands of `experiment` (engine/cli/cmd_experiment.cpp calls them).
void register_experiment_seed000(CLI::App& experiment);
void register_experiment_seed004(CLI::App& experiment);
void register_experiment_seed001(CLI::App& experiment);  // cmd_experiment_seed001.cpp
void register_experiment_seed002(CLI::App& experiment);  // cmd_experiment_seed002.cpp
void register_experiment_schedules(CLI::App& experiment);
void register_experiment_scale(CLI::App& experiment);
void register_experiment_recorded(CLI::App& experiment);
void register_experiment_seed003(CLI::App& experiment);  // cmd_siamese_experiment.cpp

}  // namespace trackassoc::cli
