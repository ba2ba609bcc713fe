// The one runner of the built `trackassoc` CLI (TRACKASSOC_CLI) for every test: runs it through
// /bin/sh and captures its exit status, stdout and stderr; CliFixture does so in a per-test
// temporary folder.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace trackassoc::testing_support {

struct CliResult {
  int status = -1;
  std::string out, err;
};

// The shell command that runs `trackassoc ARGS` with stdout and stderr sent to files `out`, `err`.
inline std::string cli_command(const std::string& args, const std::string& out, const std::string& err) {
  return std::string(TRACKASSOC_CLI) + " " + args + " >" + out + " 2>" + err;
}

inline std::string slurp_file(const std::string& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Runs `trackassoc ARGS`, its output captured in files of `dir` (which must exist). The status is
// -1 when the CLI did not exit normally (a crash).
inline CliResult run_cli(const std::string& args, const std::filesystem::path& dir) {
  const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
  const int raw = std::system(cli_command(args, out, err).c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp_file(out), slurp_file(err)};
}

class CliFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("trackassoc_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CliResult run(const std::string& args) { return run_cli(args, dir_); }
  static std::string slurp(const std::string& p) { return slurp_file(p); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  std::filesystem::path dir_;
};

}  // namespace trackassoc::testing_support
