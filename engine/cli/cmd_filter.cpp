// trackassoc filter --input F.h5 --filter cv|ca|ab|cs|cs-nn|imm --output G.h5: /measurements to
// /tracks with the chosen filter bank (engine/tracking/local_filtering.hpp).
#include <iostream>

#include "engine/cli/common.hpp"
#include "engine/tracking/local_filtering.hpp"

namespace trackassoc::cli {

void register_filter(CLI::App& app) {
  struct Args {
    CommonOptions common;
    FilterFileOptions o;
  };
  auto args = std::make_shared<Args>();
  FilterFileOptions& o = args->o;
  auto* cmd =
      app.add_subcommand("filter", "Turn /measurements into /tracks with a filter bank (HDF5 in, HDF5 out)");
  cmd->add_option("--input,-i", o.input, "Input HDF5 file with /sensors and /measurements")->required();
  add_output_option(cmd, o.output, "Output HDF5 file")->required();
  cmd->add_option(
         "--filter", o.filter,
         "cv | ca (Kalman), ab (alpha-beta, Kalata gains), cs (current statistical), cs-nn (parallel CS + "
         "network), imm (seed 002)")
      ->check(CLI::IsMember({"cv", "ca", "ab", "cs", "cs-nn", "imm"}))
      ->capture_default_str();
  // < 0: not given (the option's range [0, inf) keeps -1 out of reach)
  cmd->add_option(
         "--process-noise", o.process_noise,
         "σ of the white-noise acceleration of cv/ca/ab [m/s²] (default: the file's scenario, else 1; "
         "ab needs > 0)")
      ->check(at_least(0));
  cmd->add_option("--run", o.run, "Monte Carlo run number (selects the track-number shuffle)")
      ->check(in_range(0, std::numeric_limits<int32_t>::max()))
      ->capture_default_str();
  add_common_options(cmd, args->common);
  cmd->callback([args] {
    ThreadScope threads(args->common.threads);
    check_output_paths({{args->o.output, "--output"}}, {{args->o.input, "--input"}});
    FilterFileOptions o = args->o;
    o.seed = args->common.seed;
    const FilterFileSummary s = filter_track_file(o);
    std::cout << "filtered " << s.measurements << " measurements of " << s.sensors << " sensors with '"
              << o.filter << "': " << s.track_reports << " track reports -> " << o.output << "\n";
  });
}

}  // namespace trackassoc::cli
