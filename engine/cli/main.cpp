// trackassoc: the command-line entry point. Each subcommand lives in engine/cli/cmd_*.cpp.
// Bad input (trackassoc::InputError) prints one line on stderr and exits with status 2.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "engine/cli/common.hpp"
#include "kernels/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"trackassoc: multi-sensor track-to-track association engine"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "trackassoc 0.1.0");
  // One line per command file (engine/cli/cmd_*.cpp).
  trackassoc::cli::register_run(app);
  trackassoc::cli::register_simulate(app);
  trackassoc::cli::register_associate(app);
  trackassoc::cli::register_evaluate(app);
  trackassoc::cli::register_solve3d(app);
  trackassoc::cli::register_experiment(app);
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
