#include "engine/experiments.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "engine/version.hpp"

namespace trackassoc {

std::string find_plot_script() {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const char* dir = std::getenv("TRACKASSOC_SCRIPTS_DIR")) {
    const fs::path p = fs::path(dir) / "plot.py";
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path p = exe.parent_path().parent_path() / "scripts" / "plot.py";
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  if (fs::is_regular_file("scripts/plot.py", ec)) return "scripts/plot.py";
  return {};
}

bool run_plot_script(const std::string& args) {
  const std::string script = find_plot_script();
  if (script.empty()) {
    std::cerr << "trackassoc: warning: scripts/plot.py not found (set TRACKASSOC_SCRIPTS_DIR); no plots\n";
    return false;
  }
  const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  const std::string cmd = python + " '" + script + "' " + args;
  if (std::system(cmd.c_str()) != 0) {
    std::cerr << "trackassoc: warning: plotting failed (" << cmd << "); the HDF5 file is complete\n";
    return false;
  }
  return true;
}

void write_experiment_header(const h5::Group& root, const std::string& experiment) {
  root.write_attribute("format", std::string("trackassoc-experiment"));
  root.write_attribute("experiment", experiment);
  root.write_attribute("created_by", created_by());
}

}  // namespace trackassoc
