#include "engine/studies/experiments.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "engine/version.hpp"

namespace trackassoc {

std::string find_script(const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const char* dir = std::getenv("TRACKASSOC_SCRIPTS_DIR")) {
    const fs::path p = fs::path(dir) / name;
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path p = exe.parent_path().parent_path() / "scripts" / name;
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  if (fs::is_regular_file("scripts/" + name, ec)) return "scripts/" + name;
  return {};
}

namespace {

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

bool run_plot_script(const std::string& name, const std::vector<std::string>& args) {
  const std::string script = find_script(name);
  if (script.empty()) {
    std::cerr << "trackassoc: warning: scripts/" << name
              << " not found (set TRACKASSOC_SCRIPTS_DIR); no plots\n";
    return false;
  }
  const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  // Appended piece by piece (not python + " " + ...: GCC 12 warns -Wrestrict on that, wrongly).
  std::string cmd = python;
  cmd += ' ';
  cmd += shell_quoted(script);
  for (const auto& a : args) {
    cmd += ' ';
    cmd += shell_quoted(a);
  }
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
