#include "io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "kernels/core/error.hpp"

namespace trackassoc {

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  struct stat sa {
  }, sb{};
  const bool a_exists = ::stat(a.c_str(), &sa) == 0, b_exists = ::stat(b.c_str(), &sb) == 0;
  if (a_exists && b_exists) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (a_exists != b_exists) return false;  // one exists and the other does not
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  return (ea ? fs::absolute(a).lexically_normal() : ca) == (eb ? fs::absolute(b).lexically_normal() : cb);
}

void check_output_paths(const std::vector<OutputPath>& paths, const std::vector<InputPath>& inputs) {
  namespace fs = std::filesystem;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const OutputPath& p = paths[i];
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
    for (const InputPath& in : inputs)
      if (!in.path.empty() && same_file(p.path, in.path))
        throw InputError(who + "is the input " + (in.what.empty() ? "" : in.what + " ") + in.path +
                         " (the same file); writing it would replace the input: choose another output");
    for (std::size_t j = 0; j < i; ++j)
      if (!paths[j].path.empty() && same_file(p.path, paths[j].path))
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
