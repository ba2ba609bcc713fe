// trackassoc solvers [NAME ...]
// Lists the solver registry (engine/solvers/solver_registry.hpp): each solver's description, what it can
// do (the capability flags that associate, run and solve3d read), and its options with their
// defaults, ranges and documentation, from the options' one declaration (engine/solvers/option_fields.hpp).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/solvers/solver_registry.hpp"

namespace trackassoc::cli {
namespace {

std::string capabilities_text(const SolverCapabilities& c) {
  std::vector<std::string> can;
  if (c.tensor3) can.push_back(c.dummies ? "3-D tensor with dummies" : "3-D tensor");
  if (c.sd) can.push_back(c.sd_tensor ? "S-D with dummies (dense and sparse)" : "S-D with dummies (dense)");
  if (c.time_limit) can.push_back("time limit");
  if (c.lower_bound) can.push_back("lower bound");
  if (c.restarts) can.push_back("restarts");
  if (!c.schedules.empty()) can.push_back("schedules " + list_names(c.schedules, ", "));
  return list_names(can, ", ");
}

}  // namespace

void register_solvers(CLI::App& app) {
  auto names = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("solvers", "List the solvers: what each can do, and its --options keys");
  std::vector<std::string> known;
  for (const auto& e : all_solvers()) known.push_back(e.name);
  cmd->add_option("names", *names, "Solvers to describe (default: all): " + list_names(known, ", "));
  cmd->callback([names, known] {
    for (const std::string& n : *names)
      if (!lookup_solver(n)) throw InputError("solvers: " + unknown_name_message("solver", n, known));
    for (const auto& e : all_solvers()) {
      if (!names->empty() && std::find(names->begin(), names->end(), e.name) == names->end()) continue;
      std::cout << e.name << ": " << e.description << "\n  can: " << capabilities_text(e.capabilities)
                << "\n  --options:\n"
                << e.options_help();
    }
  });
}

}  // namespace trackassoc::cli
