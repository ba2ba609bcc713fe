// trackassoc import autoferry --scenario N --output F.h5: one Autoferry scenario's lidar and radar
// detections tracked into schema v1 /tracks (Piren NED) with its GNSS /truth;
// trackassoc experiment autoferry --output DIR: all 9 scenarios tracked, associated (the default
// pipeline) and scored on radar–lidar pairs (engine/studies/autoferry/autoferry.hpp has the rules).
#include <iostream>
#include <set>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/studies/autoferry/autoferry.hpp"
#include "engine/studies/experiments.hpp"

namespace trackassoc::cli {
namespace {

const char* kDataHelp = "The Autoferry data set folder (holding scenario2/ ... scenario22/)";
// ../shared beside the checkout (data/ is the checkout's), so the commands run from any folder.
const std::string kDefaultData = std::string(TRACKASSOC_DATA_DIR) + "/../../shared/datasets/autoferry";

std::string labelled(const std::vector<TrackLabel>& labels, int32_t sensor) {
  int n = 0, all = 0;
  for (const TrackLabel& l : labels)
    if (l.sensor == sensor) ++all, n += l.label >= 0;
  return std::to_string(n) + "/" + std::to_string(all);
}

// "1: 2/0, 2: 1/1": correct/false pairs per vessel.
std::string per_vessel(const PairScore& p) {
  std::set<int32_t> vessels;
  for (const auto& [v, n] : p.correct_by_vessel) vessels.insert(v);
  for (const auto& [v, n] : p.false_by_vessel) vessels.insert(v);
  std::string out;
  for (const int32_t v : vessels) {
    auto c = p.correct_by_vessel.find(v), f = p.false_by_vessel.find(v);
    out += (out.empty() ? "" : ", ") + std::to_string(v) + ": " +
           std::to_string(c == p.correct_by_vessel.end() ? 0 : c->second) + "/" +
           std::to_string(f == p.false_by_vessel.end() ? 0 : f->second);
  }
  return out.empty() ? "-" : out;
}

void add_row(TextTable& t, const std::string& name, const PairScore& p, const std::string& lidar,
             const std::string& radar, const std::string& breaks, double seconds) {
  t.add({name, lidar, radar, breaks, std::to_string(p.true_pairs), std::to_string(p.predicted),
         std::to_string(p.correct), std::to_string(p.unlabelled_predicted), fmt(100 * p.precision(), "%.1f"),
         fmt(100 * p.recall(), "%.1f"), per_vessel(p), fmt(seconds, "%.2f")});
}

}  // namespace

void register_autoferry(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string data = kDefaultData, output;
    int scenario = 0;
    bool no_plots = false;  // experiment: no scenarioN.png
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.get_subcommand("import")->add_subcommand(
      "autoferry",
      "One Autoferry scenario (NTNU milliAmpere, CC0): lidar and radar detections, taken from the ownship "
      "into the Piren NED frame (x north, y east; /tracks attr frame = NED), tracked per sensor by the GNN "
      "tracker (engine/studies/autoferry/autoferry.hpp states every parameter), with the GNSS truth (/truth) "
      "and each local "
      "track's truth label (/tracks/truth)");
  cmd->add_option("--data", args->data, kDataHelp)->capture_default_str();
  cmd->add_option("--scenario", args->scenario, "Scenario number: 2, 3, 4, 5, 6, 13, 16, 17 or 22")
      ->required();
  add_output_option(cmd, args->output, "Output HDF5 file")->required();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    const auto inputs = autoferry_input_files(args->data, args->scenario);
    check_output_paths({{args->output, "--output"}}, {{inputs[0], "--data"}, {inputs[1], "--data"}});
    const AutoferryOptions o;
    const AutoferryScenario sc = read_autoferry_scenario(args->data, args->scenario);
    LocalTrackingSummary summary;
    const TrackFile file = autoferry_track_file(sc, o, &summary);
    write_track_file(args->output, file);
    std::cout << "scenario " << args->scenario << ": " << sc.scans.size() << " detection entries";
    for (const auto& s : summary.sensors) {
      std::set<int32_t> kept;
      for (std::size_t i = 0; i < file.tracks.size(); ++i)
        if (file.tracks.sensor[i] == s.sensor) kept.insert(file.tracks.track[i]);
      std::cout << "; " << (s.sensor == kAutoferryLidar ? "lidar" : "radar") << " " << s.scans << " scans, "
                << s.plots << " plots, " << s.confirmed_tracks << " confirmed tracks (" << kept.size()
                << " of >= " << o.min_track_duration_s << " s kept)";
    }
    std::cout << " (" << fmt(summary.runtime_s, "%.3f") << " s) -> " << args->output << "\n";
  });

  auto eargs = std::make_shared<Args>();
  auto* exp = app.get_subcommand("experiment")
                  ->add_subcommand(
                      "autoferry",
                      "All 9 Autoferry scenarios: detections -> local tracks (lidar, radar) -> "
                      "association (the default pipeline of associate) -> radar-lidar pair "
                      "precision and recall against the GNSS truth (engine/studies/autoferry/autoferry.hpp)");
  exp->add_option("--data", eargs->data, kDataHelp)->capture_default_str();
  add_output_option(
      exp, eargs->output,
      "Output folder: scenarioN.h5 per scenario, and scenarioN.png (detections, local tracks "
      "coloured by the association, truth; scripts/plot_autoferry.py) unless --no-plots (\"\" = none)");
  exp->add_flag("--no-plots", eargs->no_plots, "Write no scenarioN.png");
  add_common_options(exp, eargs->common);
  exp->callback([eargs] {
    ThreadScope threads(eargs->common.threads);
    const AutoferryOptions o;
    const AutoferryExperimentResult r = run_autoferry_experiment(eargs->data, o, eargs->output);
    TextTable t({"scenario", "lidar tracks (labelled)", "radar tracks (labelled)", "breaks lidar/radar",
                 "true pairs", "predicted", "correct", "unlabelled", "precision %", "recall %",
                 "vessel: correct/false", "time s"});
    int32_t lidar_breaks = 0, radar_breaks = 0;
    for (const auto& s : r.scenarios) {
      const int32_t lb = track_breaks(s.labels, kAutoferryLidar),
                    rb = track_breaks(s.labels, kAutoferryRadar);
      lidar_breaks += lb;
      radar_breaks += rb;
      add_row(t, std::to_string(s.scenario), s.pairs, labelled(s.labels, kAutoferryLidar),
              labelled(s.labels, kAutoferryRadar), std::to_string(lb) + "/" + std::to_string(rb), s.seconds);
    }
    add_row(t, "all", r.total, "", "", std::to_string(lidar_breaks) + "/" + std::to_string(radar_breaks),
            r.seconds);
    t.print(std::cout);
    std::cout << "pairs: radar-lidar with >= " << o.min_overlap_s << " s overlap; label: within "
              << o.label_distance << " m of a vessel over >= " << 100 * o.label_fraction
              << " % of a track's rows\n";
    if (!eargs->output.empty()) std::cout << "wrote " << eargs->output << "/scenarioN.h5\n";
    if (!eargs->output.empty() && !eargs->no_plots &&
        run_plot_script("plot_autoferry.py", {eargs->data, eargs->output}))
      std::cout << "wrote " << eargs->output << "/scenarioN.png\n";
  });
}

}  // namespace trackassoc::cli
