// Every documented command runs as written (issue 16, Done when; issue 33: README.md and every
// docs/*.md): each `trackassoc ...` line of their code blocks, and each one-line `trackassoc ...`
// code span of their text, is checked against the built CLI. CLI11 accepts unknown flags beside --help (it
// prints the help before it checks for extras), so exit 0 of `CMD --help` alone proves nothing about the
// flags: the test reads the command's own --help instead and requires that
//   - `--help` exits 0 and its usage line names the README's subcommand chain (an unknown
//     subcommand would print its parent's help);
//   - the words after the chain are values of the command's positionals (dataset seed003);
//   - every flag the README names is an option of that command.
// Alternatives (`seed000|seed001|...`, `cv|ca|...`) are expanded, one check per alternative for a
// subcommand; brackets of optional flags ([--scenario S]) are dropped; `;` separates commands.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.hpp"

namespace trackassoc {
namespace {

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  return parts;
}

// The `trackassoc ...` commands of the README (words after `trackassoc`, brackets removed).
std::vector<std::vector<std::string>> readme_commands(const std::string& readme) {
  std::vector<std::string> lines;
  std::istringstream in(readme);
  bool fenced = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (fenced) {
      const auto hash = line.find(" #");  // a trailing comment
      std::string command = hash == std::string::npos ? line : line.substr(0, hash);
      if (command.rfind("$ ", 0) == 0) command.erase(0, 2);  // a shell prompt before the command
      lines.push_back(command);
    } else {
      static const std::regex span("`(trackassoc [^`]*)`");
      for (std::sregex_iterator it(line.begin(), line.end(), span), end; it != end; ++it)
        lines.push_back((*it)[1]);
    }
  }
  std::vector<std::vector<std::string>> commands;
  for (const auto& line : lines)
    for (const auto& part : split(line, ';')) {
      std::vector<std::string> w = words(part);
      if (w.empty() || w[0] != "trackassoc") continue;
      w.erase(w.begin());
      for (auto& x : w) std::erase_if(x, [](char c) { return c == '[' || c == ']'; });
      std::erase_if(w, [](const std::string& x) { return x.empty(); });
      commands.push_back(w);
    }
  return commands;
}

// The subcommand chain of a usage line "Usage: PROGRAM a b [OPTIONS] ...": {a, b}.
std::vector<std::string> usage_chain(const std::string& help) {
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("Usage: ", 0) == 0) {
      std::vector<std::string> w = words(line.substr(7));
      std::vector<std::string> chain;
      for (std::size_t k = 1; k < w.size() && w[k][0] != '[' && w[k] != "SUBCOMMAND"; ++k)
        chain.push_back(w[k]);
      return chain;
    }
  return {};
}

// The help text from "Positionals:" up to the next section.
std::string positionals_section(const std::string& help) {
  const auto start = help.find("Positionals:");
  if (start == std::string::npos) return "";
  const auto end = help.find("\nOptions:", start);
  return help.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Whether `flag` (e.g. --output) is one of the option names of a help text ("-o,--output TEXT").
bool has_option(const std::string& help, const std::string& flag) {
  const std::regex name("(^|\\n) +([-a-zA-Z0-9]+,)*" + flag + "([ ,=\\n]|$)");
  return std::regex_search(help, name);
}

class ReadmeCommands : public testing_support::CliFixture {
 protected:
  // Checks one command (no alternatives left in its subcommand words); the failures name it.
  void check(const std::vector<std::string>& command) {
    std::string text, path_words;
    std::vector<std::string> path, flags;
    for (const auto& w : command) {
      text += " " + w;
      if (w.rfind("-", 0) == 0) {
        if (w.rfind("--", 0) == 0) flags.push_back(w.substr(0, w.find('=')));
      } else if (flags.empty()) {
        path.push_back(w);
        path_words += " " + w;
      }
    }
    SCOPED_TRACE("documented: trackassoc" + text);
    ++checked_;
    const testing_support::CliResult r = run(path_words + " --help");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<std::string> chain = usage_chain(r.out);
    ASSERT_LE(chain.size(), path.size()) << r.out;
    ASSERT_FALSE(chain.empty()) << "the program's own help, not a subcommand's:\n" << r.out;
    for (std::size_t k = 0; k < chain.size(); ++k) EXPECT_EQ(chain[k], path[k]) << r.out;
    const std::string positionals = positionals_section(r.out);
    for (std::size_t k = chain.size(); k < path.size(); ++k)
      EXPECT_NE(positionals.find(path[k]), std::string::npos)
          << "'" << path[k] << "' is neither a subcommand nor a positional value:\n"
          << r.out;
    for (const auto& f : flags) EXPECT_TRUE(has_option(r.out, f)) << f << " is not an option:\n" << r.out;
  }
  int checked_ = 0;
};

// README.md, then docs/*.md in name order.
std::vector<std::string> documentation_files() {
  std::vector<std::string> files{TRACKASSOC_SOURCE_DIR "/README.md"};
  std::vector<std::string> docs;
  for (const auto& e : std::filesystem::directory_iterator(TRACKASSOC_SOURCE_DIR "/docs"))
    if (e.path().extension() == ".md") docs.push_back(e.path().string());
  std::sort(docs.begin(), docs.end());
  files.insert(files.end(), docs.begin(), docs.end());
  return files;
}

TEST_F(ReadmeCommands, EveryCommandNamesItsSubcommandAndFlagsAsTheCliHasThem) {
  std::size_t total = 0;
  for (const std::string& file : documentation_files()) {
    SCOPED_TRACE(file);
    const auto commands = readme_commands(slurp(file));
    total += commands.size();
    for (const auto& c : commands) {
      // Expand the alternatives of the subcommand words (seed000|seed001|...).
      std::size_t alt = c.size();
      for (std::size_t k = 0; k < c.size() && c[k][0] != '-'; ++k)
        if (c[k].find('|') != std::string::npos) alt = k;
      if (alt == c.size()) {
        check(c);
        continue;
      }
      for (const auto& a : split(c[alt], '|')) {
        std::vector<std::string> one = c;
        one[alt] = a;
        check(one);
      }
    }
  }
  ASSERT_GE(total, 30u) << "the command lines of README.md and docs/ were not found";
  EXPECT_GE(checked_, 40);
}

// The front door and the reference both hold commands, so neither file can lose them unnoticed.
TEST_F(ReadmeCommands, TheReadmeAndTheCommandReferenceBothHoldCommands) {
  EXPECT_GE(readme_commands(slurp(TRACKASSOC_SOURCE_DIR "/README.md")).size(), 6u);
  EXPECT_GE(readme_commands(slurp(TRACKASSOC_SOURCE_DIR "/docs/commands.md")).size(), 20u);
}

// The checker itself: it refuses what the CLI does not have.
TEST_F(ReadmeCommands, TheCheckerRefusesAnUnknownFlagOrSubcommand) {
  const testing_support::CliResult dataset = run("dataset seed003 --help");
  ASSERT_EQ(dataset.status, 0);
  EXPECT_TRUE(has_option(dataset.out, "--output"));
  EXPECT_FALSE(has_option(dataset.out, "--out"));  // the README's old `dataset seed003 --out`
  EXPECT_FALSE(has_option(dataset.out, "--outp"));
  const testing_support::CliResult bogus = run("experiment seed999 --help");
  ASSERT_EQ(bogus.status, 0);  // CLI11 prints `experiment`'s help
  EXPECT_EQ(usage_chain(bogus.out), std::vector<std::string>{"experiment"}) << bogus.out;
  EXPECT_EQ(positionals_section(bogus.out).find("seed999"), std::string::npos) << bogus.out;
  const auto parsed = readme_commands(
      "```\ntrackassoc a b --x 1 ; trackassoc c [--y Y]  # note --z\n$ trackassoc e\nout\n```\n`trackassoc "
      "d`");
  const std::vector<std::vector<std::string>> want{{"a", "b", "--x", "1"}, {"c", "--y", "Y"}, {"e"}, {"d"}};
  EXPECT_EQ(parsed, want);
}

}  // namespace
}  // namespace trackassoc
