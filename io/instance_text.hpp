// The S-D assignment instance text format of the public benchmark sets (docs/design.md §3):
//   line 1: number of dimensions S (3); line 2: n1 n2 n3; then n1·n2·n3 costs, first index slowest.
// And the `ap3.opt` / `bs.opt` files of known optima: one "name value" pair per line.
// And the DecompLib `.sol` files: a line "OPT: value", then one optimal tuple "i j k" per line, 1-based.
//
// What the files in benchmarks/3dap/ really contain (checked on all 120): costs are non-negative
// integers, one per line; line 2 has a trailing space; the .opt files separate name and value by
// one or two spaces; the .sol files start with a blank line. The reader accepts any whitespace and
// any finite real cost (parsed as double, stored as float: docs/design.md §2 Precision).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "kernels/assignment/assignment_types.hpp"

namespace trackassoc {

// Throws InputError naming the source and what is wrong (too few numbers, a negative size,
// garbage, a tensor larger than `max_elements`).
CostTensor3 parse_3dap_instance(const std::string& text, const std::string& source = "<string>",
                                std::size_t max_elements = std::size_t{1} << 28);
CostTensor3 read_3dap_instance(const std::string& path);
std::map<std::string, double> read_known_optima(const std::string& path);

struct Solution3File {
  double optimum = 0.0;
  std::vector<Tuple3> tuples;  // 0-based
};
Solution3File read_3dap_solution(const std::string& path);

}  // namespace trackassoc
