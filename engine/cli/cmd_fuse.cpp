// trackassoc fuse --input A.h5 [--association NAME] --rule naive|bsc|ci [--no-registration] -o OUT:
// the fused tracks of an association, written to /fused/<name> of a copy of the input at OUT
// (engine/fusion/track_fuser.hpp; atomically, never over the input: docs/design.md §2), of the
// reports corrected by the association's /registration.
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/fusion/track_fuser.hpp"
#include "io/track_validation.hpp"

namespace trackassoc::cli {

void register_fuse(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string input, output, association, name;
    std::string rule = "naive", criterion = "trace";
    double common_process_noise = 0.0, correlation = -1.0;
    bool no_registration = false;
    TrackFuserOptions o;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "fuse",
      "Fuse the local tracks of each tuple of an association into one track over time (/fused/NAME). Times: "
      "the members' report times where at least two members' spans overlap (the tuples of one target over "
      "their own time slices); the other members are predicted there by the CV model from their latest "
      "report. Tuples of one member and members that never coexist give no rows. Registration: when the "
      "file's /registration belongs to the association (its attribute association; one per file, written "
      "by the default associate) and was applied, every report is first corrected as associate corrected "
      "it (each sensor's range, azimuth, elevation, site and clock errors relative to the reference "
      "sensor removed, the position covariance widened by the estimate's uncertainty), so the fused "
      "states are of the registered reports; otherwise the reports are fused as recorded.");
  cmd->add_option("--input,-i", args->input, "HDF5 file with /tracks and /associations")->required();
  add_output_option(cmd, args->output,
                    "Where to write a copy of the input with /fused added (never the input itself)")
      ->required();
  cmd->add_option("--association", args->association,
                  "The /associations group to fuse (default: the file's only association)");
  cmd->add_option("--name", args->name, "The /fused group to write (default: the association's name)");
  cmd->add_option("--rule", args->rule,
                  "naive (independent errors, information-weighted), bsc (Bar-Shalom–Campo with the "
                  "cross-covariance), ci (covariance intersection)")
      ->check(enum_choices<FusionRule>())
      ->capture_default_str();
  cmd->add_option("--ci-criterion", args->criterion,
                  "ci: choose omega by minimising the trace or determinant")
      ->check(enum_choices<CiCriterion>())
      ->capture_default_str();
  cmd->add_option(
         "--common-process-noise", args->common_process_noise,
         "bsc: the Bar-Shalom–Campo recursion's white-noise acceleration SIGMA [m/s²] of the targets "
         "and the local CV filters (default: the file's scenario tracker.process_noise)")
      ->check(in_range(0, 1000, true));
  cmd->add_option("--correlation", args->correlation,
                  "bsc: instead of the recursion, the cross-covariance RHO·P_a^½ P_b^½, RHO in [0, 1)")
      ->check(in_range(0, 1, false, true));
  cmd->add_option("--process-noise", args->o.process_noise,
                  "White-noise acceleration σ [m/s²] moving a report to a fused time")
      ->check(in_range(0, 1000))
      ->capture_default_str();
  cmd->add_flag("--no-registration", args->no_registration,
                "Fuse the reports as recorded even when /registration belongs to the association (default: "
                "corrected by it, as associate associated them)");
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}}, {{args->input, "--input"}});  // never in place
    if (!args->name.empty())
      track_validation::check_object_name("--name", "/fused", args->name);  // before any work
    TrackFuserOptions o = args->o;
    o.rule = parse_enum<FusionRule>(args->rule, "--rule");
    o.ci.criterion = parse_enum<CiCriterion>(args->criterion, "--ci-criterion");
    o.common_process_noise = args->common_process_noise;
    o.correlation = args->correlation;
    o.registration = !args->no_registration;
    if (o.rule != FusionRule::kBarShalomCampo && (o.common_process_noise > 0.0 || o.correlation >= 0.0))
      throw InputError("--common-process-noise and --correlation apply to --rule bsc only");
    if (o.common_process_noise > 0.0 && o.correlation >= 0.0)
      throw InputError("--common-process-noise and --correlation: give one cross-covariance, not both");
    TrackFile file = read_track_file(args->input);
    const TrackFuserSummary s = fuse_track_file(file, args->association, args->name, o, args->input);
    const FusedTrackRecord& rec = file.fused.back();
    std::cout << "fused /associations/" << rec.association << " with rule " << rec.rule
              << (rec.ci_criterion.empty() ? "" : " (" + rec.ci_criterion + ")") << ": " << s.termination
              << "\n";
    std::cout << "registration: " << s.registration << "\n";
    if (o.rule == FusionRule::kBarShalomCampo)
      std::cout << "cross-covariance: "
                << (s.cross_covariance == "correlation" ? "rho = " + fmt(o.correlation) + " (given)"
                                                        : "Bar-Shalom–Campo recursion, sigma_a = " +
                                                              fmt(nlohmann::json::parse(rec.options_json)
                                                                      .at("common_process_noise")
                                                                      .get<double>()) +
                                                              " m/s² (" + s.cross_covariance_source + ")")
                << (s.shrunk_cells ? ", shrunk to a positive definite joint covariance in " +
                                         std::to_string(s.shrunk_cells) + " cells"
                                   : "")
                << "\n";
    std::cout << s.rows << " fused rows in " << fmt(s.runtime_s * 1e3, "%.1f") << " ms -> " << args->output
              << ":/fused/" << rec.name << "\n";
    write_track_file(args->output, file);
  });
}

}  // namespace trackassoc::cli
