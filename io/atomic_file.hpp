// Atomic output (docs/design.md §2): write to PATH.tmp in the same folder, then rename over PATH.
// An existing PATH is never truncated before the new content is complete.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace trackassoc {

// Calls write(tmp_path) and renames tmp_path to `path` when it returns. If write throws, the tmp
// file is removed, `path` is untouched, and the exception propagates.
void write_atomically(const std::string& path, const std::function<void(const std::string& tmp_path)>& write);

// The check every command makes on all its output files before it computes or replaces anything
// (issue 15: a failing second output must not cost the first). Each non-empty path must name a
// file, not a directory, in an existing folder it may write to; no path may be given twice; and
// no output may be one of the command's `inputs` (issue 30: `import csv --output in.csv` replaced
// its input with HDF5, exit 0). Files are compared as files, not as names: two paths of existing
// files are the same when they have the same device and inode, so a symlink, a hard link, "./"
// or ".." cannot hide an input; a path that does not exist yet is compared by its absolute,
// normalised name. Empty paths ("" = no plot, no such input) are skipped. Throws InputError
// "WHAT PATH: why", naming `what` (e.g. "--plot") when given.
struct OutputPath {
  std::string path;
  std::string what;  // the option that names it, e.g. "--output"
};
using InputPath = OutputPath;  // an input file and the option that names it, e.g. {"in.csv", "--input"}
void check_output_paths(const std::vector<OutputPath>& paths, const std::vector<InputPath>& inputs = {});

// Whether paths `a` and `b` name the same file (above: device and inode when both exist).
bool same_file(const std::string& a, const std::string& b);

// An input file `path` (named by option `what`) exists, is not a directory, and can be read;
// otherwise an InputError saying which ("--instance results/: is a directory, not an instance file").
void check_input_file(const std::string& path, const std::string& what, const std::string& kind);

}  // namespace trackassoc
