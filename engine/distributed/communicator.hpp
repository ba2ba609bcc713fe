// The ranks of a job beyond one machine (docs/design.md §8; issue 19). The engine shards Monte Carlo runs
// and connected components over ranks through this small interface, so the sharding code is the
// same in every build and unit-testable without MPI:
//   * SingleProcessCommunicator, always built: one rank; scatter and gather are copies;
//   * the MPI communicator (engine/distributed/mpi_communicator.cpp), compiled only with
//     -DTRACKASSOC_MPI=ON, over MPI_COMM_WORLD.
// Only rank 0 reads input files, writes outputs (atomically, io/atomic_file.hpp) and prints.
// Kernels never see a communicator (docs/design.md §1): the ranks exchange engine-level work items.
//
// The collectives move byte buffers (engine/distributed/byte_buffer.hpp). Failures are agreed by
// what the buffers carry (engine/distributed/sharding.hpp), so a rank never waits for a rank that
// has given up; an error that escapes outside that protocol aborts the job (main.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "engine/distributed/byte_buffer.hpp"

namespace trackassoc::distributed {

// Bytes this rank sent and received through the collectives (issue 19 item 6: communication
// volume). Rank 0's counts are the whole job's traffic, since every message goes to or from it.
struct CommunicationStats {
  uint64_t bytes_sent = 0, bytes_received = 0, messages = 0;
};

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Rank 0 sends parts[r] to every rank r (parts.size() == size(); ignored on other ranks);
  // every rank returns its own part.
  virtual Bytes scatter(const std::vector<Bytes>& parts) = 0;
  // Every rank sends `mine`; rank 0 returns all of them in rank order, the others nothing.
  virtual std::vector<Bytes> gather(const Bytes& mine) = 0;
  // Ends every rank of the job with `code` (MPI_Abort): the last resort for an error that left
  // other ranks waiting in a collective.
  [[noreturn]] virtual void abort(int code) = 0;

  bool root() const { return rank() == 0; }
  const CommunicationStats& stats() const { return stats_; }
  // A collective exchange has begun and not finished; an error escaping now must abort the job.
  bool exchange_open() const { return exchange_open_; }
  void set_exchange_open(bool open) { exchange_open_ = open; }
  // Rank 0 only: the other ranks wait for a scatter (sharded associate); an error before it must
  // release them (release_waiting_ranks, engine/distributed/sharding.hpp).
  bool ranks_waiting() const { return ranks_waiting_; }
  void set_ranks_waiting(bool waiting) { ranks_waiting_ = waiting; }

 protected:
  CommunicationStats stats_;

 private:
  bool exchange_open_ = false, ranks_waiting_ = false;
};

class SingleProcessCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  Bytes scatter(const std::vector<Bytes>& parts) override { return parts.at(0); }
  std::vector<Bytes> gather(const Bytes& mine) override { return {mine}; }
  [[noreturn]] void abort(int code) override;
};

// Thrown on a rank that must end with `code` without printing: rank 0 prints the one error line
// of the job (docs/design.md §2, exit 2 for bad input, 1 for an internal error).
class SilentExit : public std::exception {
 public:
  explicit SilentExit(int code) : code_(code) {}
  int code() const { return code_; }
  const char* what() const noexcept override { return "exit without a message (another rank reports)"; }

 private:
  int code_;
};

// The process's communicator. main() creates one World: in an MPI build started by mpirun (or
// any launcher that sets OMPI_COMM_WORLD_SIZE / PMIX_RANK / PMI_SIZE) it initialises MPI and
// finalises it on destruction; otherwise, and in the default build, it is one process.
class World {
 public:
  World(int& argc, char**& argv);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;
};
Communicator& world();

#ifdef TRACKASSOC_WITH_MPI
// engine/distributed/mpi_communicator.cpp
std::unique_ptr<Communicator> make_mpi_communicator(int& argc, char**& argv);
void finalize_mpi();
#endif

}  // namespace trackassoc::distributed
