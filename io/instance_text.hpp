// The S-D assignment instance text format of the public benchmark sets (DESIGN §3):
//   line 1: number of dimensions S (3); line 2: n1 n2 n3; then n1·n2·n3 costs, first index slowest.
// And the `ap3.opt` / `bs.opt` files of known optima: one "name value" pair per line.
#pragma once

#include <map>
#include <string>

#include "kernels/assignment_types.hpp"

namespace trackassoc {

// Throws InputError naming the source and what is wrong (too few numbers, a negative size,
// garbage, a tensor larger than `max_elements`).
CostTensor3 parse_3dap_instance(const std::string& text, const std::string& source = "<string>",
                                std::size_t max_elements = std::size_t{1} << 28);
CostTensor3 read_3dap_instance(const std::string& path);
std::map<std::string, double> read_known_optima(const std::string& path);

}  // namespace trackassoc
