// trackassoc associate --input F.h5 --output G.h5 [--solver NAME] [--3d | --sparse | --sd]
// The input is a simulation file or a recorded track file (schema v1). The output holds the
// input's content plus /associations/<name>/.
// Default: every sensor of the file, the sparse S-D pipeline (engine/sparse_sd_pipeline.hpp) with
// the calibrated gate, all-pairs cost, solver lr+ls (also lr, exact). A 3-D solver name (greedy,
// pairwise, hopfield, ...) or --3d selects the three-sensor tensor pipeline below, which takes
// exactly three sensors: a file with more needs --sensors (never a silent drop).
// Dense 3-D path: the n1·n2·n3 cost tensor (engine/pipeline.hpp); a track set whose tensor
// exceeds --memory-budget is refused before any work, with a pointer to --sparse. Sparse path
// (--sparse): gated candidate tuples and connected components, each solved by the same solver
// (engine/sparse_pipeline.hpp); the same /associations/<name>/ record, its options attribute
// carrying "sparse": true.
#include <algorithm>
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/cli/table.hpp"
#include "engine/fuzzy_pipeline.hpp"
#include "engine/pipeline.hpp"
#include "engine/pipeline_sd.hpp"
#include "engine/siamese_track_file.hpp"
#include "engine/solver_registry.hpp"
#include "engine/sparse_pipeline.hpp"
#include "engine/sparse_sd_pipeline.hpp"
#include "engine/workflow.hpp"
#include "io/siamese_model_file.hpp"

namespace trackassoc::cli {
namespace {

// Replaces any association of the same name by `rec` and writes the file (atomically).
void store_association(TrackFile& file, const AssociationRecord& rec, const std::string& output) {
  std::erase_if(file.associations, [&](const AssociationRecord& a) { return a.name == rec.name; });
  file.associations.push_back(rec);
  write_track_file(output, file);
}

}  // namespace

void register_associate(CLI::App& app) {
  struct Args {
    CommonOptions common;
    PipelineFlags pipeline;
    std::string input, output, solver, name;
    HopfieldFlags hopfield;  // merged into --options
    bool sd = false, three_d = false;
    std::string model = TRACKASSOC_DATA_DIR "/models/siamese_seed003.h5";  // --solver siamese
  };
  auto args = std::make_shared<Args>();
  std::string solver_help =
      "Solver. Default pipeline (every sensor, sparse S-D with dummies): lr+ls (default), lr, exact. "
      "3-D assignment solvers (three sensors, --3d implied for names not above):";
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
  cmd->add_flag("--sd", args->sd,
                "S-D formulation with a dummy per sensor (any number of sensors; solvers lr, lr+ls, exact, "
                "chnn-pseudo). Implied by more than three --sensors");
  cmd->add_flag(
      "--3d", args->three_d,
      "The three-sensor cost-tensor pipeline (seed 000 Eq. 3) for any solver, e.g. --solver lr --3d");
  add_pipeline_options(cmd, args->pipeline);
  add_hopfield_flags(cmd, args->hopfield, true);
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}});
    const PipelineOptions options = resolve(args->pipeline);
    nlohmann::json solver_options = parse_solver_options(args->pipeline.solver_options);
    const bool explicit_pipeline = args->sd || args->three_d || args->pipeline.sparse;
    if (int(args->sd) + int(args->three_d) + int(args->pipeline.sparse) > 1)
      throw InputError("--sd, --3d and --sparse choose different pipelines: give at most one");
    if (args->solver.empty()) args->solver = "lr+ls";
    merge_hopfield_flags(args->hopfield, args->solver, solver_options);
    const bool special = args->solver == "fuzzy" || args->solver == "ftaa" || args->solver == "siamese";
    const auto& sparse_sd = sparse_sd_solver_names();
    if (!explicit_pipeline && !special && options.sensors.size() != 3 &&
        std::find(sparse_sd.begin(), sparse_sd.end(), args->solver) != sparse_sd.end()) {
      SparseSDOptions so;
      so.pipeline = options;
      TrackFile file = read_track_file(args->input);
      std::vector<StageReport> stages;
      AssociationRecord rec =
          associate_sparse_sd(file, args->solver, solver_options, args->common.seed, so, &stages);
      if (!args->name.empty()) rec.name = args->name;
      store_association(file, rec, args->output);
      std::cout << "associated the tracks of " << file.sensors.size() << " sensors (sparse S-D, "
                << nlohmann::json::parse(rec.options_json).value("components", 0) << " components) with '"
                << args->solver << "': objective " << fmt(rec.objective) << ", " << rec.num_tuples()
                << " tuples, " << fmt(1e3 * rec.runtime_s, "%.2f") << " ms -> " << args->output << "\n";
      std::cout << "stages:";
      for (const auto& st : stages)
        std::cout << " " << st.name << " " << fmt(1e3 * st.seconds, "%.1f") << " ms;";
      const auto info = nlohmann::json::parse(rec.options_json);
      std::cout << " candidate pairs " << info.value("candidate_pairs", 0) << ", gated "
                << info.value("gated_pairs", 0) << ", fallback components "
                << info.value("fallback_components", 0) << "\n";
      return;
    }
    if (args->solver == "fuzzy" || args->solver == "ftaa") {  // not a 3-D tensor solver (seed 001)
      if (args->pipeline.sparse)
        throw InputError("--sparse: applies to the 3-D assignment solvers, not to '" + args->solver + "'");
      const FuzzyPipelineOptions fuzzy =
          fuzzy_pipeline_options(parse_enum<FusionMethod>(args->solver, "--solver"), solver_options);
      TrackFile file = read_track_file(args->input);
      const std::string name = args->name.empty() ? args->solver : args->name;
      const FuzzyPipelineResult res = associate_fuzzy(file, fuzzy, name);
      write_track_file(args->output, file);
      std::cout << "associated " << res.packets.num_local() << " local tracks (" << res.packets.size()
                << " packets) with '" << args->solver << "': " << res.fusion.num_system_tracks
                << " system tracks, " << res.association.num_tuples() << " tuples, "
                << fmt(1e3 * res.fusion.summary.wall_time_s, "%.2f") << " ms -> " << args->output << "\n";
      return;
    }
    if (args->sd || args->solver == "chnn-pseudo" || options.sensors.size() > 3 ||
        options.sensors.size() == 2) {
      if (args->pipeline.sparse)
        throw InputError("--sparse: applies to the three-sensor pipeline, not to the S-D formulation (--sd)");
      require_sd_solver(args->solver);  // fail on an unknown name before reading anything
      TrackFile file = read_track_file(args->input);
      const SDProblem problem = build_sd_problem(file, options);
      AssociationRecord rec =
          solve_sd_association(problem, args->solver, solver_options, args->common.seed, options);
      if (!args->name.empty()) rec.name = args->name;
      store_association(file, rec, args->output);
      std::string dims;
      for (const auto& a : problem.aligned) dims += (dims.empty() ? "" : "x") + std::to_string(a.n_tracks());
      std::cout << "associated " << dims << " tracks of " << problem.S() << " sensors (S-D) with '"
                << args->solver << "': objective " << fmt(rec.objective) << ", lower bound "
                << fmt(rec.lower_bound) << ", " << rec.num_tuples() << " tuples, "
                << fmt(1e3 * rec.runtime_s, "%.2f") << " ms -> " << args->output << "\n";
      return;
    }
    if (args->solver == "siamese") {  // two sensors' plot sequences, not a 3-D tensor (seed 003)
      const SiameseTrackFileOptions siamese = siamese_track_file_options(solver_options);
      const LoadedSiameseModel model = read_siamese_model(args->model);  // before any other work
      TrackFile file = read_track_file(args->input);
      const std::string name = args->name.empty() ? args->solver : args->name;
      SiameseTrackFileResult res = associate_siamese_tracks(file, model.model, siamese, name);
      res.record.seed = args->common.seed;
      store_association(file, res.record, args->output);
      if (res.points_outside_domain > 0)
        std::cerr << "note: " << res.points_outside_domain << " of " << res.points
                  << " points lie outside the model's training domain (the shipped model: the 100 x 100 km "
                     "area +-30 km, times 0-50 s); its probabilities there are extrapolations (see "
                     "--options time_origin)\n";
      std::cout << "associated " << res.tracks[0] << "x" << res.tracks[1] << " tracks of sensors "
                << res.sensor_ids[0] << " and " << res.sensor_ids[1]
                << " with 'siamese': " << res.record.num_tuples() << " tuples, "
                << fmt(1e3 * res.record.runtime_s, "%.2f") << " ms -> " << args->output << "\n";
      return;
    }
    find_solver(args->solver);  // fail on an unknown name before reading anything
    TrackFile file = read_track_file(args->input);
    AssociationRecord rec;
    std::string summary;
    if (args->pipeline.sparse) {
      SparsePipelineOptions sparse_options;
      sparse_options.pipeline = options;
      const SparseAssociationProblem problem = build_sparse_association_problem(file, sparse_options);
      rec =
          solve_sparse_association(problem, args->solver, solver_options, args->common.seed, sparse_options);
      summary = std::to_string(problem.aligned[0].n_tracks()) + "x" +
                std::to_string(problem.aligned[1].n_tracks()) + "x" +
                std::to_string(problem.aligned[2].n_tracks()) +
                " tracks (sparse: " + std::to_string(problem.components.count) + " components)";
    } else {
      require_dense_tensor_fits(file, options);
      const AssociationProblem problem = build_association_problem(file, options);
      rec = solve_association(problem, args->solver, solver_options, args->common.seed, options);
      summary = std::to_string(problem.tensor.n1) + "x" + std::to_string(problem.tensor.n2) + "x" +
                std::to_string(problem.tensor.n3) + " tracks";
    }
    if (!args->name.empty()) rec.name = args->name;
    store_association(file, rec, args->output);
    std::cout << "associated " << summary << " with '" << args->solver << "': objective "
              << fmt(rec.objective) << ", " << rec.num_tuples() << " tuples, "
              << fmt(1e3 * rec.runtime_s, "%.2f") << " ms -> " << args->output << "\n";
  });
}

}  // namespace trackassoc::cli
