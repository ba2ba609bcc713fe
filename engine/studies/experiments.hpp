// Pieces shared by the paper experiments (docs/design.md §5, `trackassoc experiment NAME`; each study's
// subcommand is registered in engine/cli/cmd_experiment*.cpp through finish_study_command): the
// plot invocation and the experiment file header.
#pragma once

#include <string>
#include <vector>

#include "io/hdf5_wrapper.hpp"

namespace trackassoc {

// scripts/NAME (plot.py, plot_scale.py), the experiments' PNG plotters: $TRACKASSOC_SCRIPTS_DIR/NAME,
// else <executable>/../scripts/NAME, else ./scripts/NAME; empty when none exists.
std::string find_script(const std::string& name);

// The one plot invocation of every command that plots (experiment seed001, seed002, scale): runs
// `/usr/bin/python3 scripts/SCRIPT ARGS...` (python3 on PATH when /usr/bin has none), each argument
// shell-quoted. Returns false, after a warning on stderr, when the script or matplotlib is missing
// or the plot fails: plots are a convenience, the HDF5 file is the result.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args);

// The root attributes every experiment file starts with: format = "trackassoc-experiment",
// experiment = NAME, created_by (engine/version.hpp).
void write_experiment_header(const h5::Group& root, const std::string& experiment);

}  // namespace trackassoc
