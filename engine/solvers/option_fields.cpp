#include "engine/solvers/option_fields.hpp"

#include "engine/solvers/solver_registry.hpp"

namespace trackassoc {

void throw_unknown_option_key(const std::string& solver, const std::string& key,
                              const std::vector<std::string>& known) {
  throw InputError("solver '" + solver + "' options: " + unknown_name_message("key", key, known));
}

}  // namespace trackassoc
