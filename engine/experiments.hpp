// The paper experiments (DESIGN §5): `trackassoc experiment NAME`. engine/cli/cmd_experiment.cpp
// creates the `experiment` subcommand and calls one add_experiment_<name> per paper; each adds its
// own sub-subcommand (options, callback) to `experiment`.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "io/hdf5_wrapper.hpp"

namespace trackassoc {

// scripts/plot.py for the experiments' PNG plots: $TRACKASSOC_SCRIPTS_DIR/plot.py, else
// <executable>/../scripts/plot.py, else ./scripts/plot.py; empty when none exists.
std::string find_plot_script();

// Runs `/usr/bin/python3 plot.py ARGS` (falls back to python3 on PATH). Returns false, after a
// warning on stderr, when the script or matplotlib is missing or the plot fails: plots are a
// convenience, the HDF5 file is the result.
bool run_plot_script(const std::string& args);

// The root attributes every experiment file starts with: format = "trackassoc-experiment",
// experiment = NAME, created_by (engine/version.hpp).
void write_experiment_header(const h5::Group& root, const std::string& experiment);

}  // namespace trackassoc
