// trackassoc simulate --scenario S.json --output F.h5: targets, measurements and local tracks.
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/simulation/simulation_io.hpp"

namespace trackassoc::cli {

void register_simulate(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string scenario = "seed000", output;
    int run = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("simulate", "Simulate a scenario: truth, measurements and local tracks (HDF5)");
  cmd->add_option("--scenario", args->scenario, "Scenario JSON file or embedded name")->capture_default_str();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->required();
  cmd->add_option("--run", args->run, "Monte Carlo run number (selects the random stream)")
      ->check(in_range(0, std::numeric_limits<int32_t>::max()))
      ->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}}, {{args->scenario, "--scenario"}});
    const Scenario scenario = load_scenario(args->scenario);
    SimulationResult sim = simulate(scenario, args->common.seed, args->run);
    const std::size_t measurements = sim.measurements.size(), reports = sim.tracks.size();
    write_track_file(args->output, simulation_to_track_file(scenario, std::move(sim)));
    std::cout << "simulated '" << scenario.name << "': " << scenario.sensors.size() << " sensors, "
              << measurements << " measurements, " << reports << " track reports -> " << args->output << "\n";
  });
}

}  // namespace trackassoc::cli
