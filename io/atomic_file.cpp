#include "io/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "kernels/error.hpp"

namespace trackassoc {

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
