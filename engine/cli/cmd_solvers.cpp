// trackassoc solvers [NAME ...]
// Lists the solver registry (engine/solvers/solver_registry.hpp): each solver's description, what it can
// do (the capability flags that associate, run and solve3d read), and its options with their
// defaults, ranges and documentation, from the options' one declaration (engine/solvers/option_fields.hpp).
// It also lists the solvers `associate --solver` accepts that are whole pipelines rather than
// registry entries (the seed 001 fusion centre fuzzy and ftaa, the seed 003 siamese), with the
// --options keys their pipelines read (issue 30: every solver associate accepts is listed).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/pipeline/fuzzy_pipeline.hpp"
#include "engine/pipeline/siamese_track_file.hpp"
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

// The solvers of `associate` that are pipelines of their own (engine/pipeline/associators.cpp):
// name, description, what they can do, and their --options help.
struct PipelineSolver {
  std::string name, description, can;
  std::function<std::string()> options_help;
};

const std::vector<PipelineSolver>& pipeline_solvers() {
  static const std::vector<PipelineSolver> solvers = [] {
    auto fusion = [](FusionMethod m) {
      return [m] {
        FuzzyPipelineOptions defaults;
        defaults.method = m;
        return fuzzy_pipeline_option_fields(m).help(defaults);
      };
    };
    const std::string centre =
        "seed 001 fusion centre over all sensors (associate --solver NAME; also writes /system_tracks/NAME)";
    return std::vector<PipelineSolver>{
        {"fuzzy", "fuzzy association with temporary tracks and reliabilities (seed 001)", centre,
         fusion(FusionMethod::kFuzzy)},
        {"ftaa", "fuzzy track-to-track association algorithm, FTAA (seed 001's baseline)", centre,
         fusion(FusionMethod::kFtaa)},
        {"siamese", "Siamese BiLSTM pair classifier and a LAP (seed 003, TTCSN)",
         "two sensors' tracks (associate --solver siamese --model FILE)",
         [] { return siamese_track_file_option_fields().help(SiameseTrackFileOptions{}); }},
    };
  }();
  return solvers;
}

}  // namespace

void register_solvers(CLI::App& app) {
  auto names = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("solvers", "List the solvers: what each can do, and its --options keys");
  std::vector<std::string> known;
  for (const auto& e : all_solvers()) known.push_back(e.name);
  for (const auto& e : pipeline_solvers()) known.push_back(e.name);
  cmd->add_option("names", *names, "Solvers to describe (default: all): " + list_names(known, ", "));
  cmd->callback([names, known] {
    for (const std::string& n : *names)
      if (std::find(known.begin(), known.end(), n) == known.end())
        throw InputError("solvers: " + unknown_name_message("solver", n, known));
    auto wanted = [&](const std::string& n) {
      return names->empty() || std::find(names->begin(), names->end(), n) != names->end();
    };
    for (const auto& e : all_solvers())
      if (wanted(e.name))
        std::cout << e.name << ": " << e.description << "\n  can: " << capabilities_text(e.capabilities)
                  << "\n  --options:\n"
                  << e.options_help();
    for (const auto& e : pipeline_solvers())
      if (wanted(e.name))
        std::cout << e.name << ": " << e.description << "\n  can: " << e.can << "\n  --options:\n"
                  << e.options_help();
  });
}

}  // namespace trackassoc::cli
