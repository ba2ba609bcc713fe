// trackassoc: the command-line entry point. Each subcommand lives in engine/cli/cmd_*.cpp.
// Bad input (trackassoc::InputError) prints one line on stderr and exits with status 2.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <iostream>

#include "engine/cli/common.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"trackassoc: multi-sensor track-to-track association engine"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "trackassoc 0.1.0");
  // The memory budget is global (io/memory_budget.hpp); it may be given before or after the
  // subcommand, which passes options it does not know to its parent (fallthrough, inherited).
  app.fallthrough();
  app.add_option_function<double>(
      "--memory-budget",
      [](double mib) {
        if (!(mib > 0.0 && mib < 1e12))
          throw trackassoc::InputError("--memory-budget: expected a size > 0 [MiB], got " +
                                       std::to_string(mib));
        trackassoc::set_memory_budget_bytes(static_cast<std::size_t>(std::max(1.0, mib * 1048576.0)));
      },
      "Most memory [MiB] one input file, scenario or cost tensor may need; a larger request is refused "
      "before it is allocated (default: half of the physical memory, " +
          std::to_string(trackassoc::default_memory_budget_bytes() >> 20) +
          " MiB here; the dense cost tensor is also capped at 2048 MiB unless this is given)");
  // One line per command file (engine/cli/cmd_*.cpp).
  trackassoc::cli::register_run(app);
  trackassoc::cli::register_simulate(app);
  trackassoc::cli::register_associate(app);
  trackassoc::cli::register_evaluate(app);
  trackassoc::cli::register_fuse(app);
  trackassoc::cli::register_dataset(app);
  trackassoc::cli::register_train_siamese(app);
  trackassoc::cli::register_solve3d(app);
  trackassoc::cli::register_solvers(app);
  trackassoc::cli::register_filter(app);
  trackassoc::cli::register_import(app);
  trackassoc::cli::register_export(app);
  trackassoc::cli::register_experiment(app);
  trackassoc::cli::register_autoferry(app);  // after import and experiment: adds to both
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const trackassoc::InputError& e) {
    std::cerr << "trackassoc: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "trackassoc: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
