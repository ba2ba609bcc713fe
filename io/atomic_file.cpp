#include "io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>

#include "kernels/core/error.hpp"

namespace trackassoc {

void check_output_paths(const std::vector<OutputPath>& paths) {
  namespace fs = std::filesystem;
  std::set<fs::path> seen;
  for (const OutputPath& p : paths) {
    if (p.path.empty()) continue;
    const std::string who = (p.what.empty() ? "" : p.what + " ") + p.path + ": ";
    const fs::path target(p.path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    std::error_code ec;
    if (fs::is_directory(target, ec))
      throw InputError(who + "is a directory; expected the name of a file to write");
    if (!fs::exists(folder, ec))
      throw InputError(who + "output folder '" + folder.string() + "' does not exist");
    if (!fs::is_directory(folder, ec)) throw InputError(who + "'" + folder.string() + "' is not a folder");
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
      throw InputError(who + "output folder '" + folder.string() + "' is not writable");
    const fs::path canonical = fs::weakly_canonical(target, ec);
    if (!seen.insert(ec ? target : canonical).second)
      throw InputError(who + "named twice as an output; each output needs its own file");
  }
}

void check_input_file(const std::string& path, const std::string& what, const std::string& kind) {
  namespace fs = std::filesystem;
  const std::string who = (what.empty() ? "" : what + " ") + path + ": ";
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(who + "no such file");
  if (fs::is_directory(path, ec)) throw InputError(who + "is a directory, not " + kind);
  if (::access(path.c_str(), R_OK) != 0)
    throw InputError(who + "cannot read " + kind + ": " + std::strerror(errno));
}

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(path + ": output folder '" + folder.string() + "' does not exist");
  if (fs::is_directory(target, ec)) throw InputError(path + ": output path is a directory");
  const std::string tmp = path + ".tmp";
  try {
    write(tmp);
  } catch (const InputError& e) {
    // A failed write (a full disk) is reported under the name the user gave, with what survives.
    fs::remove(tmp, ec);
    std::string what = e.what();
    if (what.rfind(tmp + ": ", 0) == 0) what = path + what.substr(tmp.size());
    throw InputError(what + (fs::exists(target, ec) ? "; " + path + " is unchanged" : ""));
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot rename " + tmp + " into place: " + reason);
  }
}

}  // namespace trackassoc
