// trackassoc associate --input F.h5 --output G.h5 [--solver NAME] [--3d | --sparse | --sd]
// The input is a simulation file or a recorded track file (schema v1). The output holds the
// input's content plus /associations/<name>/ (and /system_tracks/<name>/ for fuzzy and ftaa).
// Default: every sensor of the file, the sparse S-D pipeline (engine/pipeline/sparse_sd_pipeline.hpp) with
// the calibrated gate, all-pairs cost, solver lr+ls (also lr, exact). A 3-D solver name (greedy,
// pairwise, hopfield, ...) or --3d selects the three-sensor tensor pipeline, which takes exactly
// three sensors: a file with more needs --sensors (never a silent drop). --sparse: the same on
// gated candidate tuples and connected components (engine/pipeline/sparse_pipeline.hpp). The path is
// chosen, and run, by the association interface (engine/pipeline/associator.hpp); this command parses the
// flags, calls it, writes the file and prints, ending with the unassociated local tracks of each
// sensor (those in no tuple of two or more). --plots F.png draws the recording as a map with the
// association (engine/report/association_map.hpp; --svg for SVG).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "engine/cli/association_flags.hpp"
#include "engine/cli/common.hpp"
#include "engine/cli/hopfield_flags.hpp"
#include "engine/cli/table.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/distributed/shard_items.hpp"
#include "engine/pipeline/associator.hpp"
#include "engine/pipeline/pipeline_sd.hpp"
#include "engine/pipeline/sparse_pipeline.hpp"
#include "engine/pipeline/sparse_sd_components.hpp"
#include "engine/pipeline/sparse_sd_pipeline.hpp"
#include "engine/pipeline/track_hygiene.hpp"
#include "engine/report/association_map.hpp"
#include "engine/solvers/solver_registry.hpp"
#include "io/track_validation.hpp"
#include "kernels/core/stopwatch.hpp"

namespace trackassoc::cli {
namespace {

// Wall times of consecutive phases: lap(name) closes the phase that started at the last lap (or at
// construction); text() lists them, "read 1.23 s, write 0.45 s".
class PhaseClock {
 public:
  void lap(const char* name) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.2f s", text_.empty() ? "" : ", ", name, seconds_since(t_));
    text_ += buf;
    t_ = std::chrono::steady_clock::now();
  }
  const std::string& text() const { return text_; }

 private:
  std::chrono::steady_clock::time_point t_ = std::chrono::steady_clock::now();
  std::string text_;
};

// What `associate` prints: the summary's full report (engine/pipeline/associator.hpp), its first
// line with the output file; siamese's note on points outside the model's domain to stderr.
void print_outcome(const AssociationSummary& s, const std::string& output) {
  if (s.path == AssociationPath::kSiamese && s.points_outside_domain > 0)
    std::cerr << "note: " << s.points_outside_domain << " of " << s.points
              << " points lie outside the model's training domain (the shipped model: the 100 x 100 km "
                 "area +-30 km, times 0-50 s); its probabilities there are extrapolations (see "
                 "--options time_origin)\n";
  const std::string brief = s.BriefReport(), full = s.FullReport();  // full starts with brief
  std::cout << brief << " -> " << output << full.substr(brief.size());
}

}  // namespace

void register_associate(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    std::string input, output, solver, name, plot;
    bool svg = false;
    HopfieldFlags hopfield;  // merged into --options
    bool sd = false, three_d = false;
    bool no_segments = false, no_registration = false, no_split = false, no_stitch = false,
         no_family_wise_veto = false;
    double segment_overlap = SegmentOptions{}.max_overlap_s;
    int32_t reference_sensor = -1;
    std::vector<int32_t> duplicate_sensors;
    std::string model = TRACKASSOC_DATA_DIR "/models/siamese_seed003.h5";  // --solver siamese
  };
  auto args = std::make_shared<Args>();
  const std::vector<std::string> sparse_sd = sparse_sd_solver_names();  // the default first
  std::string solver_help =
      "Solver. Default pipeline (every sensor, sparse S-D with dummies): " + sparse_sd.front() + " (default)";
  for (std::size_t i = 1; i < sparse_sd.size(); ++i) solver_help += ", " + sparse_sd[i];
  solver_help += ". 3-D assignment solvers (three sensors, --3d implied for names not above):";
  for (const auto& e : solver_registry()) solver_help += " " + e.name;
  solver_help +=
      "; or a seed 001 fusion centre over all sensors: fuzzy, ftaa (also writes /system_tracks/NAME)"
      "; or siamese: the seed 003 Siamese BiLSTM on two sensors (--model)";
  auto* cmd = app.add_subcommand("associate", "Associate the local tracks of every sensor of a track file");
  cmd->add_option("--input,-i", args->input, "Input HDF5 track file (schema v1)")->required();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file (input content + the association)")
      ->required();
  cmd->add_option("--solver", args->solver, solver_help);
  cmd->add_option("--model", args->model,
                  "--solver siamese: model file from train-siamese (default: the shipped seed 003 model)")
      ->capture_default_str();
  cmd->add_option("--name", args->name, "Group name under /associations (default: the solver name)");
  cmd->add_option(
      "--plots", args->plot,
      "Draw the recording as a map with the association: tracks coloured by output target, "
      "unassociated in grey, wrong links in red and missed targets dashed where truth exists (PNG)");
  cmd->add_flag("--svg", args->svg, "--plots as SVG (a .png name becomes .svg)");
  cmd->add_flag(
      "--sd", args->sd,
      "S-D formulation with a dummy per sensor as one dense tensor (any number of sensors; solvers " +
          list_names(sd_solver_names(), ", ") +
          "): the default path's tuple cost on the whole problem, not per component. --sensors never implies "
          "it");
  cmd->add_flag(
      "--3d", args->three_d,
      "The three-sensor cost-tensor pipeline (seed 000 Eq. 3) for any solver, e.g. --solver lr --3d");
  cmd->add_flag(
      "--no-segments", args->no_segments,
      "Default pipeline: keep the assignment's tuples, one track per sensor per target (default: the "
      "segments of a target that follow each other on one sensor, after a track break, join it; "
      "engine/pipeline/track_segments.hpp)");
  cmd->add_flag(
      "--no-registration", args->no_registration,
      "Default pipeline: associate the reports as recorded (default: joint registration and "
      "association: fit each sensor's range, azimuth (elevation), site and clock errors relative to a "
      "reference sensor on the linked tuples, and when they are significant correct the reports and "
      "re-associate until the tuples stop changing; the estimate goes to /registration and is "
      "printed; engine/pipeline/registration_stage.hpp)");
  cmd->add_flag(
      "--no-split", args->no_split,
      "Default pipeline: keep every recorded (sensor, track) key as one track (default: a key that "
      "pauses and then jumps where its own motion cannot take it, a recycled track number, and two keys "
      "of one sensor that jump at one scan where each continues the other, a swap at a crossing, are "
      "split into new local tracks before the association; /tracks/source_track keeps the recorded number; "
      "engine/pipeline/track_hygiene.hpp)");
  cmd->add_flag("--no-family-wise-veto", args->no_family_wise_veto,
                "Default pipeline: a coexisting pair outside the gate forbids every tuple that holds it "
                "(default: only when it fails the family-wise gate 1 - (1 - p)/(S(S-1)/2) of a tuple of "
                "the S sensors too, Bonferroni's level; between the two it may join a tuple linked through "
                "gated-in pairs, at its positive link cost; docs/design.md 4.3)");
  cmd->add_flag(
      "--no-stitch", args->no_stitch,
      "Default pipeline: keep output targets that never coexist apart (default: track segment "
      "association joins a target whose first report continues another's last, within 180 s, "
      "by constant velocity with a quiet (3 m/s^2 or more, learnt per file) or manoeuvring (20 m/s^2) "
      "allowance, as one assignment of positive-evidence joins: a target handed over between sensors or "
      "re-tracked after a gap; engine/pipeline/track_stitching.hpp)");
  cmd->add_option(
      "--reference-sensor", args->reference_sensor,
      "Default pipeline: the /sensors id the registration holds fixed, a sensor you trust (default: "
      "the one with the most local tracks); `fuse` then estimates in its frame, else in the "
      "sensors' information-weighted average frame");
  cmd->add_option("--segment-overlap", args->segment_overlap,
                  "Default pipeline: the report overlap [s] two segments of one sensor may have and still "
                  "follow each other (a coasting old track and its successor)")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--duplicate-sensors", args->duplicate_sensors,
                  "Default pipeline: sensor ids whose tracker may hold two tracks of one target at once (an "
                  "extended target in two clusters, e.g. a lidar on a long hull); such a track joins the "
                  "target when it passes the full-state duplicate gate chi2_D(0.999) with its twin at every "
                  "one of >= 3 common times, and the segment rules (gated in with the target on another "
                  "sensor, failing no gate; engine/pipeline/track_segments.hpp). Default: none")
      ->delimiter(',');
  add_pipeline_options(cmd, args->pipeline);
  add_hopfield_flags(cmd, args->hopfield, true);
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    auto& comm = distributed::world();
    // The inputs: the track file, and the model of --solver siamese.
    const std::vector<InputPath> inputs{{args->input, "--input"},
                                        {args->solver == "siamese" ? args->model : "", "--model"}};
    args->plot = report::picture_path(args->plot, args->svg);
    if (comm.size() == 1) check_output_paths({{args->output, "--output"}, {args->plot, "--plots"}}, inputs);
    if (!args->name.empty())  // before any work, not when the output is written
      track_validation::check_object_name("--name", "/associations", args->name);
    AssociatorOptions request;
    request.pipeline = resolve(args->pipeline);
    request.solver_options = parse_solver_options(args->pipeline.solver_options);
    request.sd = args->sd;
    request.three_d = args->three_d;
    request.sparse = args->pipeline.sparse;
    if (!args->solver.empty()) request.solver = args->solver;
    request.seed = args->common.seed;
    request.name = args->name;
    request.siamese_model = args->model;
    request.segments.enabled = !args->no_segments;
    request.registration.enabled = !args->no_registration;
    request.split.enabled = !args->no_split;
    request.stitching.enabled = !args->no_stitch;
    request.family_wise_veto = !args->no_family_wise_veto;
    request.segments.max_overlap_s = args->segment_overlap;
    request.registration.reference_sensor = args->reference_sensor;
    request.segments.duplicate_sensors = args->duplicate_sensors;
    if (!args->duplicate_sensors.empty() && args->no_segments)
      throw InputError(
          "--duplicate-sensors: duplicates join targets in the segment pass; drop --no-segments");
    request.validate();  // --sd, --3d, --sparse: at most one, before the Hopfield flags' errors
    merge_hopfield_flags(args->hopfield, request.solver, request.solver_options);
    // More than one MPI rank (docs/design.md §8): the components of the default path and of --sparse are
    // shared out; rank 0 reads, builds, writes and prints, the other ranks only solve what it sends
    // them (serve_sd_components, serve_sparse_components; engine/distributed/shard_items.hpp).
    // Everything above is the same on every rank.
    if (comm.size() > 1) {
      const AssociationPath path = choose_association_path(request);
      if (path != AssociationPath::kSparseSD && path != AssociationPath::kSparse3D)
        throw InputError("associate: only the default pipeline (sparse S-D, no --3d/--sd, solver " +
                         list_names(sparse_sd_solver_names(), ", ") +
                         ") and --sparse are sharded over MPI ranks (got " + std::to_string(comm.size()) +
                         " ranks); run the others as one process");
      if (!comm.root())
        return path == AssociationPath::kSparse3D ? serve_sparse_components(comm) : serve_sd_components(comm);
      comm.set_ranks_waiting(true);  // until rank 0 scatters their work, or its error (main.cpp)
      request.ranks = &comm;
      check_output_paths({{args->output, "--output"}, {args->plot, "--plots"}}, inputs);
    }
    const auto associator = make_associator(request);  // every check before the file is read
    // The phases' wall times, printed on stderr with TRACKASSOC_MPI_STATS (the serial remainder of
    // a sharded run: docs/mpi.md).
    PhaseClock clock;
    TrackFile file = read_track_file(args->input);
    clock.lap("read");
    const TrackSplitSummary split = split_recorded_keys(file, request);
    clock.lap("split");
    AssociationOutcome outcome = associator->associate(file);
    distributed::end_items(comm);  // the other ranks' serve loop returns (no-op on one process)
    clock.lap("associate");
    outcome.summary.split = split;
    store_outcome(file, outcome);
    write_track_file(args->output, file);
    clock.lap("write");
    if (std::getenv("TRACKASSOC_MPI_STATS")) std::cerr << "phases: " << clock.text() << "\n";
    print_outcome(outcome.summary, args->output);
    if (!args->plot.empty()) {
      report::write_association_map(args->plot, report::picture_format(args->plot, args->svg), file,
                                    outcome.record,
                                    "trackassoc associate: '" + outcome.record.name + "' on " + args->input);
      std::cout << "drew " << args->plot << "\n";
    }
  });
}

}  // namespace trackassoc::cli
