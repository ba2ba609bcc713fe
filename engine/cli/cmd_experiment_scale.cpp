// trackassoc experiment scale (issue 6): the sparse path from 10² to 10⁴ targets per sensor.
// Prints the table (time per stage, peak memory, correct rate, dense beside it where it fits),
// writes DIR/scale.h5 (the result, layout in engine/experiment_scale.hpp) and, for a quick look,
// DIR/scale.csv and DIR/scale.json, all atomically, and draws DIR/scale.png from the HDF5 file
// with scripts/plot_scale.py (/usr/bin/python3 with h5py and matplotlib).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/experiment_scale.hpp"
#include "engine/solver_registry.hpp"
#include "io/atomic_file.hpp"

namespace trackassoc::cli {

void register_experiment_scale(CLI::App& experiment) {
  struct Args {
    CommonOptions common;
    ScaleExperimentOptions options;
    std::string solver_options = "{}";
    std::string out = "results/scale";
    bool no_isolate = false, no_plot = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = experiment.add_subcommand(
      "scale",
      "Sparse association from 10^2 to 10^4 targets per sensor: time and peak memory per stage, "
      "correct rate, dense path beside it where it fits");
  auto& o = args->options;
  cmd->add_option("--sizes", o.sizes, "Targets per sensor, comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(at_least(1));
  cmd->add_option("--dense-max", o.dense_max, "Run the dense path too up to this size")
      ->capture_default_str()
      ->check(at_least(0));
  cmd->add_option("--solver", o.solver, "Solver for every component (and the dense path)")
      ->capture_default_str();
  cmd->add_option("--options", args->solver_options, "Solver options as a JSON object")
      ->capture_default_str();
  cmd->add_option("--density", o.density, "Targets per 100 km^2 of ground")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--gate", o.gate_probability, "Chi-square gate probability")
      ->capture_default_str()
      ->check(in_range(0, 1, true, true));
  cmd->add_option("--duration", o.tracks.duration, "Track set duration [s]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--sigma-pos", o.tracks.sigma_pos, "Local track position error sigma [m]")
      ->capture_default_str()
      ->check(above(0));
  cmd->add_option("--p-seen", o.tracks.p_seen, "Probability that a sensor holds a track of a target")
      ->capture_default_str()
      ->check(in_range(0, 1));
  cmd->add_option("--min-lifetime", o.tracks.min_lifetime_fraction,
                  "Each local track covers a random part of the duration, at least this fraction (1 = all)")
      ->capture_default_str()
      ->check(in_range(0, 1, true));
  cmd->add_flag_function(
      "--two-d", [args](int64_t) { args->options.tracks.three_d = false; }, "2-D targets (default 3-D)");
  cmd->add_flag("--no-isolate", args->no_isolate,
                "Run every size in this process (peak memory is then cumulative)");
  cmd->add_flag("--no-plot", args->no_plot, "Do not call scripts/plot_scale.py");
  cmd->add_option("--out", args->out, "Output folder")->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ScaleExperimentOptions o = args->options;
    o.seed = args->common.seed;
    o.threads = args->common.threads;
    o.isolate = !args->no_isolate;
    o.solver_options = parse_solver_options(args->solver_options);
    o.validate();
    find_solver(o.solver);
    std::filesystem::create_directories(args->out);
    const bool tty = isatty(STDERR_FILENO);
    auto rows = run_scale_experiment(o, [&](const ScaleRow& r) {
      if (tty) std::cerr << "scale: n = " << r.n << " done in " << r.total_s << " s\n";
    });
    std::cout << "experiment scale: 3 sensors, solver '" << o.solver << "', density " << o.density
              << " targets / 100 km^2, gate " << o.gate_probability << ", threads "
              << (o.threads ? std::to_string(o.threads) : std::string("all")) << "\n\n"
              << scale_table(rows);
    const double slope = scaling_exponent(rows, 1000);
    std::printf(
        "\nlog-log slope of total time vs n for n >= 1000: %.2f (n log n gives about 1.1 here, n^2 gives "
        "2)\n",
        slope);
    const std::string csv = args->out + "/scale.csv", json = args->out + "/scale.json",
                      h5 = args->out + "/scale.h5";
    write_atomically(csv, [&](const std::string& tmp) { std::ofstream(tmp) << scale_csv(rows); });
    nlohmann::json j = {{"options",
                         {{"sizes", o.sizes},
                          {"dense_max", o.dense_max},
                          {"solver", o.solver},
                          {"solver_options", o.solver_options},
                          {"density_per_100km2", o.density},
                          {"gate_probability", o.gate_probability},
                          {"duration", o.tracks.duration},
                          {"sigma_pos", o.tracks.sigma_pos},
                          {"p_seen", o.tracks.p_seen},
                          {"min_lifetime_fraction", o.tracks.min_lifetime_fraction},
                          {"three_d", o.tracks.three_d},
                          {"seed", o.seed},
                          {"threads", o.threads}}},
                        {"loglog_slope_n_ge_1000", slope},
                        {"rows", nlohmann::json::array()}};
    for (const auto& r : rows) j["rows"].push_back(r.to_json());
    write_atomically(json, [&](const std::string& tmp) { std::ofstream(tmp) << j.dump(1) << "\n"; });
    write_scale_h5(h5, rows, j["options"], slope);
    std::cout << "wrote " << h5 << ", " << csv << ", " << json << "\n";
    if (!args->no_plot) {
      const std::string script = std::string(TRACKASSOC_DATA_DIR) + "/../scripts/plot_scale.py";
      const std::string png = args->out + "/scale.png";
      // The Debian interpreter has python3-matplotlib (scripts/setup.sh); a python3 earlier on PATH may not.
      const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
      const std::string command = python + " '" + script + "' '" + h5 + "' '" + png + "'";
      if (std::filesystem::exists(script) && std::system(command.c_str()) == 0)
        std::cout << "wrote " << png << "\n";
      else
        std::cout << "plot skipped (run: " << command << ")\n";
    }
  });
}

}  // namespace trackassoc::cli
