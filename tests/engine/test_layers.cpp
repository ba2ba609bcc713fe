// The layers of the tree (docs/design.md §1): kernels include only kernels, io only io and kernels,
// and inside engine/ a folder includes only from itself and the folders before it in the order that
// docs/design.md states on its "engine layers:" line (read from there, so the page and the check
// cannot drift apart). Every #include "kernels/…", "io/…" or "engine/…" of the tree is checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kRoot = TRACKASSOC_SOURCE_DIR;

// The engine folders, lowest first, from docs/design.md's "engine layers:" line.
std::vector<std::string> engine_layers() {
  std::ifstream in(kRoot / "docs" / "design.md");
  std::string line;
  while (std::getline(in, line)) {
    const auto at = line.find("engine layers:");
    if (at == std::string::npos) continue;
    std::string list = line.substr(at + 14);
    list.erase(std::remove(list.begin(), list.end(), '`'), list.end());
    std::vector<std::string> layers;
    std::stringstream ss(list);
    std::string name;
    while (std::getline(ss, name, ',')) {
      name.erase(0, name.find_first_not_of(' '));
      name.erase(name.find_last_not_of(' ') + 1);
      if (!name.empty()) layers.push_back(name);
    }
    return layers;
  }
  return {};
}

// Why `file` (a path from the root) may not include `target` (the include's path), or "" when it
// may. An engine folder missing from `layers` is itself a finding.
std::string violation(const std::string& file, const std::string& target,
                      const std::vector<std::string>& layers) {
  auto top = [](const std::string& p) { return p.substr(0, p.find('/')); };
  auto engine_folder = [](const std::string& p) {  // "" for a file at engine/'s top
    const std::string rest = p.substr(7);
    const auto slash = rest.find('/');
    return slash == std::string::npos ? std::string() : rest.substr(0, slash);
  };
  const std::string from = top(file), to = top(target);
  if (from == "kernels" && to != "kernels") return "a kernel includes from " + to;
  if (from == "io" && to == "engine") return "io includes from engine";
  if (from != "engine" || to != "engine") return "";
  const std::string a = engine_folder(file), b = engine_folder(target);
  if (b.empty() || a == b) return "";
  auto rank = [&](const std::string& f) {
    const auto it = std::find(layers.begin(), layers.end(), f);
    return it == layers.end() ? -1 : static_cast<int>(it - layers.begin());
  };
  if (a.empty()) return "a file at engine/'s top includes from engine/" + b;
  if (rank(a) < 0) return "engine/" + a + " is not on docs/design.md's engine layers line";
  if (rank(b) < 0) return "engine/" + b + " is not on docs/design.md's engine layers line";
  if (rank(b) > rank(a)) return "engine/" + a + " includes from engine/" + b + ", a layer above it";
  return "";
}

TEST(Layers, TheDesignPageNamesEveryEngineFolderOnce) {
  const std::vector<std::string> layers = engine_layers();
  ASSERT_FALSE(layers.empty()) << "docs/design.md has no 'engine layers:' line";
  std::set<std::string> named(layers.begin(), layers.end());
  EXPECT_EQ(named.size(), layers.size()) << "a folder is named twice";
  for (const auto& entry : fs::directory_iterator(kRoot / "engine"))
    if (entry.is_directory()) {
      EXPECT_TRUE(named.count(entry.path().filename().string())) << entry.path();
    }
  for (const auto& name : layers) EXPECT_TRUE(fs::is_directory(kRoot / "engine" / name)) << name;
}

TEST(Layers, TheRuleFindsABackwardInclude) {
  const std::vector<std::string> layers{"solvers", "pipeline", "fusion", "report"};
  EXPECT_NE(violation("engine/pipeline/a.cpp", "engine/fusion/b.hpp", layers), "");
  EXPECT_EQ(violation("engine/fusion/a.cpp", "engine/pipeline/b.hpp", layers), "");
  EXPECT_EQ(violation("engine/pipeline/a.cpp", "engine/pipeline/b.hpp", layers), "");
  EXPECT_EQ(violation("engine/report/a.cpp", "engine/version.hpp", layers), "");
  EXPECT_NE(violation("engine/version.cpp", "engine/pipeline/b.hpp", layers), "");
  EXPECT_NE(violation("engine/studies/a.cpp", "engine/pipeline/b.hpp", layers), "");  // unnamed folder
  EXPECT_NE(violation("kernels/core/a.hpp", "io/b.hpp", layers), "");
  EXPECT_NE(violation("io/a.cpp", "engine/pipeline/b.hpp", layers), "");
  EXPECT_EQ(violation("io/a.cpp", "kernels/core/b.hpp", layers), "");
}

TEST(Layers, NoIncludePointsUp) {
  const std::vector<std::string> layers = engine_layers();
  ASSERT_FALSE(layers.empty());
  const std::regex include_line(R"(^\s*#\s*include\s+"((kernels|io|engine)/[^"]+)\")");
  std::size_t files = 0, includes = 0;
  for (const char* folder : {"kernels", "io", "engine"})
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".hpp" && ext != ".cpp" && ext != ".h")) continue;
      ++files;
      const std::string file = fs::relative(entry.path(), kRoot).generic_string();
      std::ifstream in(entry.path());
      std::string line;
      std::smatch m;
      while (std::getline(in, line))
        if (std::regex_search(line, m, include_line)) {
          ++includes;
          const std::string why = violation(file, m[1].str(), layers);
          EXPECT_EQ(why, "") << file << " includes " << m[1].str();
        }
    }
  EXPECT_GT(files, 300u);
  EXPECT_GT(includes, 500u);
}

}  // namespace
