// trackassoc: the command-line entry point. Each subcommand lives in engine/cli/cmd_*.cpp.
// Bad input (trackassoc::InputError) prints one line on stderr and exits with status 2.
// Under mpirun (an MPI build, docs/design.md §8) every rank runs this; only rank 0 prints, and only
// `experiment` and `associate` run on more than one rank (engine/distributed/communicator.hpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <sstream>

#include "engine/cli/common.hpp"
#include "engine/cli/study_command.hpp"
#include "engine/distributed/communicator.hpp"
#include "engine/distributed/sharding.hpp"
#include "io/memory_budget.hpp"
#include "kernels/core/error.hpp"
#include "kernels/core/printable_text.hpp"

namespace {

// The end of a failed command on rank `comm.rank()`: rank 0 prints the one line; another rank is
// silent when every rank failed alike (the same arguments, before any exchange), and otherwise
// reports itself and ends the job, since the others may wait for it in a collective.
int fail(trackassoc::distributed::Communicator& comm, const std::string& line, int code) {
  release_waiting_ranks(comm, std::current_exception());
  if (comm.root())
    std::cerr << line << "\n";
  else if (comm.exchange_open())
    std::cerr << "rank " << comm.rank() << ": " << line << "\n";
  if (comm.size() > 1 && comm.exchange_open()) {
    std::cerr << std::flush;
    comm.abort(code);
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  trackassoc::distributed::World world(argc, argv);
  auto& comm = trackassoc::distributed::world();
  CLI::App app{"trackassoc: multi-sensor track-to-track association engine"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "trackassoc 0.1.0");
  // The memory budget is global (io/memory_budget.hpp); it may be given before or after the
  // subcommand, which passes options it does not know to its parent (fallthrough, inherited).
  app.fallthrough();
  app.add_option_function<double>(
      "--memory-budget",
      [](double mib) {
        if (!(mib > 0.0 && mib < 1e12))
          throw trackassoc::InputError("--memory-budget: expected a size > 0 [MiB], got " +
                                       std::to_string(mib));
        trackassoc::set_memory_budget_bytes(static_cast<std::size_t>(std::max(1.0, mib * 1048576.0)));
      },
      "Most memory [MiB] one input file, scenario or cost tensor may need; a larger request is refused "
      "before it is allocated (default: half of the physical memory, " +
          std::to_string(trackassoc::default_memory_budget_bytes() >> 20) +
          " MiB here; the dense cost tensor is also capped at 2048 MiB unless this is given)");
  // One line per command file (engine/cli/cmd_*.cpp).
  trackassoc::cli::register_run(app);
  trackassoc::cli::register_simulate(app);
  trackassoc::cli::register_associate(app);
  trackassoc::cli::register_evaluate(app);
  trackassoc::cli::register_fuse(app);
  trackassoc::cli::register_dataset(app);
  trackassoc::cli::register_train_siamese(app);
  trackassoc::cli::register_solve3d(app);
  trackassoc::cli::register_solvers(app);
  trackassoc::cli::register_filter(app);
  trackassoc::cli::register_import(app);
  trackassoc::cli::register_export(app);
  trackassoc::cli::register_experiment(app);
  trackassoc::cli::register_autoferry(app);  // after import and experiment: adds to both
  // More than one rank: the commands that shard (docs/mpi.md) and no other, so
  // no command writes one file from several ranks.
  std::string sharded = "`associate`";
  for (const auto& s : trackassoc::cli::sharded_studies()) sharded += ", `experiment " + s + "`";
  auto refuse_ranks = [&comm, sharded](CLI::App* sub, const std::string& name) {
    sub->preparse_callback([name, sharded, &comm](std::size_t) {
      if (comm.size() > 1)
        throw trackassoc::InputError(name + ": runs as one process; under mpirun only " + sharded +
                                     " are sharded over ranks (got " + std::to_string(comm.size()) +
                                     " ranks)");
    });
  };
  for (CLI::App* sub : app.get_subcommands({})) {
    const std::string name = sub->get_name();
    if (name == "associate") continue;
    if (name != "experiment")
      refuse_ranks(sub, name);
    else
      for (CLI::App* study : sub->get_subcommands({}))
        if (!trackassoc::cli::sharded_studies().count(study->get_name()))
          refuse_ranks(study, "experiment " + study->get_name());
  }
  try {
    app.parse(argc, argv);
    if (comm.size() > 1 && comm.root() && std::getenv("TRACKASSOC_MPI_STATS")) {
      const auto& st = comm.stats();  // every message goes to or from rank 0: the job's traffic
      std::cerr << "mpi: " << comm.size() << " ranks; rank 0 sent " << st.bytes_sent << " B, received "
                << st.bytes_received << " B in " << st.messages << " messages";
      const auto& times = trackassoc::distributed::last_shard_times();
      for (std::size_t r = 0; r < times.wall_s.size(); ++r)
        std::cerr << (r ? ", " : "; work per rank [wall/CPU s]: ") << times.wall_s[r] << "/"
                  << times.cpu_s[r];
      std::cerr << "\n";
    }
  } catch (const CLI::ParseError& e) {
    std::ostringstream null_out, null_err;  // rank 0 alone prints help and usage errors
    const int code = comm.root() ? app.exit(e) : app.exit(e, null_out, null_err);
    return code == 0 ? 0 : 2;
  } catch (const trackassoc::distributed::SilentExit& e) {
    return e.code();
  } catch (const trackassoc::InputError& e) {
    // printable_text: the previews of input in messages are escaped where they are made (a NUL
    // would end what()); this keeps any byte that slipped through off the terminal too.
    return fail(comm, "trackassoc: error: " + trackassoc::printable_text(e.what()), 2);
  } catch (const std::exception& e) {
    return fail(comm, "trackassoc: internal error: " + trackassoc::printable_text(e.what()), 1);
  }
  return 0;
}
