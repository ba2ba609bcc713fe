// trackassoc filter --input F.h5 --filter cv|ca|ab|cs|cs-nn|imm --output G.h5
//
// Turns /measurements into /tracks with the chosen filter bank, one bank per sensor
// (engine/simulation_tracker.hpp: perfect measurement-to-track origin from /measurements/target,
// clutter ignored, two-point initialisation, shuffled local track numbers). Everything else of the
// input is copied except /associations and /metrics, which described the old tracks. For the IMM
// the model probabilities go to the extra dataset /tracks/model_prob (N×M, float64; additive to
// schema v1) with the attribute /tracks/models naming the columns.
#include <hdf5.h>

#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/simulation_tracker.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_wrapper.hpp"
#include "io/scenario_json.hpp"
#include "io/track_file.hpp"
#include "io/track_validation.hpp"

namespace trackassoc::cli {

namespace {

void add_model_probabilities(const std::string& path, const LocalTrackingResult& r,
                             const std::string& models) {
  h5::silence_library_errors();
  h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (!f.valid()) throw InputError(path + ": cannot reopen the new file to add /tracks/model_prob");
  h5::Handle g(H5Gopen2(f.get(), "/tracks", H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw InputError(path + ": /tracks: missing in the new file");
  h5::Group tracks(path, std::move(g), "/tracks");
  tracks.write_dataset("model_prob", std::span<const double>(r.model_prob),
                       {static_cast<hsize_t>(r.tracks.size()), static_cast<hsize_t>(r.num_models)});
  tracks.write_attribute("models", models);
  if (f.close() < 0) throw InputError(path + ": failed to close after adding /tracks/model_prob");
}

}  // namespace

void register_filter(CLI::App& app) {
  struct Args {
    CommonOptions common;
    std::string input, output, filter = "cv";
    double process_noise = -1.0;  // < 0: not given (the option's range [0, inf) keeps -1 out of reach)
    int run = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("filter", "Turn /measurements into /tracks with a filter bank (HDF5 in, HDF5 out)");
  cmd->add_option("--input,-i", args->input, "Input HDF5 file with /sensors and /measurements")->required();
  cmd->add_option("--output,-o", args->output, "Output HDF5 file")->required();
  cmd->add_option(
         "--filter", args->filter,
         "cv | ca (Kalman), ab (alpha-beta, Kalata gains), cs (current statistical), cs-nn (parallel CS + "
         "network), imm (seed 002)")
      ->check(CLI::IsMember({"cv", "ca", "ab", "cs", "cs-nn", "imm"}))
      ->capture_default_str();
  cmd->add_option(
         "--process-noise", args->process_noise,
         "σ of the white-noise acceleration of cv/ca/ab [m/s²] (default: the file's scenario, else 1; "
         "ab needs > 0)")
      ->check(at_least(0));
  cmd->add_option("--run", args->run, "Monte Carlo run number (selects the track-number shuffle)")
      ->check(in_range(0, std::numeric_limits<int32_t>::max()))
      ->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->output, "--output"}});
    TrackFile file = read_track_file(args->input);
    if (!file.measurements || file.measurements->size() == 0)
      throw InputError(args->input +
                       ": /measurements: missing or empty; `filter` needs measurements to track");
    LocalTrackerSpec spec;
    StateLayout layout = file.tracks.layout;
    if (!file.scenario_json.empty()) {
      const Scenario sc = parse_scenario_json(file.scenario_json, args->input + ":/scenario");
      spec = sc.tracker;
      layout = sc.layout;
    }
    track_validation::check_measurement_noise(args->input, *file.measurements, file.sensors,
                                              layout == StateLayout::kXYZ_VXVYVZ);
    spec.filter = args->filter;
    if (args->process_noise >= 0.0) spec.process_noise = args->process_noise;
    if (spec.filter == "ab" && !(spec.process_noise > 0.0))
      throw InputError("--process-noise: the alpha-beta filter's Kalata gains need σ > 0 [m/s²], got " +
                       std::to_string(spec.process_noise));
    const LocalTrackingResult r =
        track_measurements(*file.measurements, file.sensors, layout, spec, args->common.seed, args->run);
    file.tracks = r.tracks;
    file.associations.clear();
    file.metrics.clear();
    write_atomically(args->output, [&](const std::string& tmp) {
      write_track_file(tmp, file);
      if (r.num_models > 0) add_model_probabilities(tmp, r, "cs-nn,ca");
    });
    std::cout << "filtered " << file.measurements->size() << " measurements of " << file.sensors.size()
              << " sensors with '" << args->filter << "': " << r.tracks.size() << " track reports -> "
              << args->output << "\n";
  });
}

}  // namespace trackassoc::cli
