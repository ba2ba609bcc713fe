// Atomic output (DESIGN §2): write to PATH.tmp in the same folder, then rename over PATH.
// An existing PATH is never truncated before the new content is complete.
#pragma once

#include <functional>
#include <string>

namespace trackassoc {

// Calls write(tmp_path) and renames tmp_path to `path` when it returns. If write throws, the tmp
// file is removed, `path` is untouched, and the exception propagates.
void write_atomically(const std::string& path, const std::function<void(const std::string& tmp_path)>& write);

}  // namespace trackassoc
