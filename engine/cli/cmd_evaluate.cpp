// trackassoc evaluate --input G.h5 [--output H.h5]: correct / false / missed association rates of
// every association in the file by per-row truth (the rule: engine/pipeline/metrics.hpp, stated in
// --help) and its pair recalls and precision (engine/pipeline/pair_metrics.hpp), written to
// /metrics/<name>/, and with /truth the position RMSE
// of every /fused group beside each sensor's (engine/fusion/fused_accuracy.hpp), written to the
// /fused group, in a copy of the input at --output (atomically); without --output it only prints: no
// output ever replaces an input (docs/design.md §2).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/fusion/fused_accuracy.hpp"
#include "engine/pipeline/metrics.hpp"
#include "engine/pipeline/pair_metrics.hpp"
#include "io/hdf5_wrapper.hpp"

namespace trackassoc::cli {

namespace {

// The fused position RMSE of every /fused group beside each sensor's (stored in the groups).
void print_fused_accuracy(TrackFile& file, std::ostream& os) {
  if (file.fused.empty()) return;
  if (!file.truth) {
    os << "\n/fused: no /truth in the file, so no position RMSE\n";
    return;
  }
  std::vector<std::string> header{"fused", "rule", "rows", "fused RMSE [m]"};
  for (const Sensor& s : file.sensors)
    header.push_back("sensor " + std::to_string(s.id) + " RMSE [m] (rows)");
  TextTable table(header);
  for (FusedTrackRecord& rec : file.fused) {
    const FusedAccuracy a = evaluate_fused(file.tracks, file.sensors, *file.truth, rec);
    store_fused_accuracy(rec, a);
    std::vector<std::string> row{rec.name,
                                 rec.rule + (rec.ci_criterion.empty() ? "" : " (" + rec.ci_criterion + ")"),
                                 std::to_string(a.fused_rows), fmt(a.fused_rmse, "%.2f")};
    for (std::size_t s = 0; s < a.sensor_rmse.size(); ++s)
      row.push_back(fmt(a.sensor_rmse[s], "%.2f") + " (" + std::to_string(a.sensor_rows[s]) + ")");
    table.add(row);
  }
  os << "\n";
  table.print(os);
}

// "88.00 % (12 of 14)", or "- (none)" when there is nothing to count. Two decimals: the pair
// figures are read against bars such as 99.5 %, which one decimal would round 99.46 % up to.
std::string share(double rate, int64_t part, int64_t whole) {
  if (whole == 0) return "- (none)";
  return fmt(100.0 * rate, "%.2f %%") + " (" + std::to_string(part) + " of " + std::to_string(whole) + ")";
}

}  // namespace

void register_evaluate(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string input, output;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "evaluate",
      "Score the associations of a file against its ground truth, by per-row truth. Scoring rule: a key is "
      "a local track as /tracks holds it, (sensor, track) (after associate split a recycled track number "
      "into new tracks; /tracks/source_track keeps the recorded one). A key's target is the majority of its "
      "rows' /tracks/truth: the target id most of its rows carry (ties: the lowest id; a key none of whose "
      "rows has a target, all -1, is a false track). A target whose keys lie on >= 2 of the association's "
      "sensors needs association. An output group is the rows (tuples) sharing /associations/NAME/target "
      "(each tuple alone when the association has no target numbers). A target is correct when one output "
      "group holds exactly its keys; false when one of its keys shares a group with a key of another "
      "target or a false track; missed otherwise (rates are fractions of the targets that need "
      "association). A false tuple joins keys of different targets, or a false track with anything. Pairs "
      "(engine/pipeline/pair_metrics.hpp): keys in one tuple, or in tuples of one target number, are one "
      "output target; coexisting pairs are keys of one target on two sensors whose report intervals "
      "overlap, fragment pairs are consecutive keys of one target on one sensor; each recall is the "
      "fraction in one output target, and pair precision the fraction of the key pairs in one output "
      "target that have the same target (a false track linked with anything is wrong). With "
      "/fused and /truth it also prints the fused position RMSE of each /fused group beside each "
      "sensor's, over the same targets and times (the members' reports at the fused times).");
  cmd->add_option("--input,-i", args->input, "HDF5 file with /tracks/truth and /associations")->required();
  cmd->add_option("--output,-o", args->output,
                  "Where to write a copy of the input with /metrics (and the /fused RMSE) added; without "
                  "it, evaluate only prints (the input is never rewritten)");
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}});
    TrackFile file = read_track_file(args->input);
    // The reader fills a missing /tracks/truth with -1 (it is optional); then it is missing, not
    // "-1 everywhere". The file read cleanly above, so it is opened here in process.
    if (!h5::File::open_read_only(args->input).root().open_group("tracks").has("truth"))
      throw InputError(
          args->input +
          ": /tracks/truth: missing dataset; evaluate scores each association against the target "
          "id of every /tracks row (int32, -1 = a false track)");
    if (file.associations.empty())
      throw InputError(args->input + ": /associations is empty; run `trackassoc associate` first");
    TextTable table({"association", "targets", "correct", "false", "missed", "false tuples"});
    TextTable pairs({"association", "coexisting pairs linked", "fragment pairs linked", "pair precision"});
    bool any_truth = false;
    for (const auto& rec : file.associations) {
      const AssociationMetrics m = evaluate_association(file.tracks, file.sensors, rec);
      if (!m.has_truth) continue;
      any_truth = true;
      std::erase_if(file.metrics, [&](const MetricsRecord& r) { return r.name == rec.name; });
      const PairMetrics p = evaluate_pairs(file.tracks, file.sensors, rec);
      file.metrics.push_back(to_metrics_record(rec.name, m));
      add_pair_metrics(file.metrics.back(), p);
      pairs.add({rec.name, share(p.coexisting_recall, p.coexisting_linked, p.coexisting),
                 share(p.fragment_recall, p.fragments_linked, p.fragments),
                 share(p.precision, p.linked_pairs_same_truth, p.linked_pairs)});
      table.add({rec.name, std::to_string(m.targets), percent(m.correct_rate), percent(m.false_rate),
                 percent(m.missed_rate),
                 std::to_string(m.false_tuples) + " of " + std::to_string(m.linked_tuples)});
    }
    if (!any_truth)
      throw InputError(args->input +
                       ": /tracks/truth holds no target ids (-1 everywhere); nothing to evaluate");
    table.print(std::cout);
    std::cout << "\n";
    pairs.print(std::cout);
    print_fused_accuracy(file, std::cout);
    if (!args->output.empty()) write_track_file(args->output, file);
  });
}

}  // namespace trackassoc::cli
