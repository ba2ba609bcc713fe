// The single-process communicator and the process's World (engine/distributed/communicator.hpp).
#include "engine/distributed/communicator.hpp"

#include <cstdlib>

namespace trackassoc::distributed {
namespace {

std::unique_ptr<Communicator>& world_slot() {
  static std::unique_ptr<Communicator> comm = std::make_unique<SingleProcessCommunicator>();
  return comm;
}

#ifdef TRACKASSOC_WITH_MPI
bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}
bool mpi_initialised = false;
#endif

}  // namespace

void SingleProcessCommunicator::abort(int code) { std::_Exit(code); }

World::World([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef TRACKASSOC_WITH_MPI
  // Without a launcher the MPI build runs as one process and never starts MPI, so its plain
  // commands behave (and cost) exactly as the default build's.
  if (launched_by_mpirun()) {
    world_slot() = make_mpi_communicator(argc, argv);
    mpi_initialised = true;
  }
#endif
}

World::~World() {
#ifdef TRACKASSOC_WITH_MPI
  if (mpi_initialised) {
    world_slot().reset(new SingleProcessCommunicator);
    finalize_mpi();
  }
#endif
}

Communicator& world() { return *world_slot(); }

}  // namespace trackassoc::distributed
