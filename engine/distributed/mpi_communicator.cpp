// The MPI communicator over MPI_COMM_WORLD (engine/distributed/communicator.hpp), compiled only
// with -DTRACKASSOC_MPI=ON (OpenMPI from Debian, docs/design.md §8). Sizes travel as uint64 through
// MPI_Scatter / MPI_Gather; the bytes then go point to point in chunks of at most 1 GiB, so a
// part may exceed MPI's int counts. Only the main thread calls MPI (MPI_THREAD_FUNNELED); oneTBB
// workers inside a rank never do. A rank that waits (for rank 0's scatter while it builds, for
// the others' results) sleeps between tests of its request instead of spinning, so waiting ranks
// leave the cores to working ones when ranks share cores (mpirun --oversubscribe).
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "engine/distributed/communicator.hpp"

namespace trackassoc::distributed {
namespace {

constexpr std::size_t kChunk = std::size_t{1} << 30;
constexpr int kTag = 19;  // issue 19

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Waits for `request`, testing it every 200 µs (a waiting rank costs no core).
void wait_politely(MPI_Request& request, const char* what) {
  int done = 0;
  for (;;) {
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void send_bytes(const Bytes& b, int to) {
  for (std::size_t off = 0; off < b.size(); off += kChunk) {
    const int n = static_cast<int>(std::min(kChunk, b.size() - off));
    MPI_Request request;
    check(MPI_Isend(b.data() + off, n, MPI_BYTE, to, kTag, MPI_COMM_WORLD, &request), "MPI_Isend");
    wait_politely(request, "MPI_Isend");
  }
}

void receive_bytes(Bytes& b, int from) {
  for (std::size_t off = 0; off < b.size(); off += kChunk) {
    const int n = static_cast<int>(std::min(kChunk, b.size() - off));
    MPI_Request request;
    check(MPI_Irecv(b.data() + off, n, MPI_BYTE, from, kTag, MPI_COMM_WORLD, &request), "MPI_Irecv");
    wait_politely(request, "MPI_Irecv");
  }
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator(int& argc, char**& argv) {
    int provided = 0;
    check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  Bytes scatter(const std::vector<Bytes>& parts) override {
    std::vector<uint64_t> sizes(size_);
    if (rank_ == 0) {
      if (static_cast<int>(parts.size()) != size_) throw std::logic_error("scatter: one part per rank");
      for (int r = 0; r < size_; ++r) sizes[r] = parts[r].size();
    }
    uint64_t mine = 0;
    // Non-blocking, tested politely: the other ranks wait here while rank 0 reads and builds (a
    // blocking MPI_Scatter spins, and took a core from rank 0 when ranks share the cores).
    MPI_Request request;
    check(MPI_Iscatter(sizes.data(), 1, MPI_UINT64_T, &mine, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request),
          "MPI_Iscatter");
    wait_politely(request, "MPI_Iscatter");
    if (rank_ == 0) {
      for (int r = 1; r < size_; ++r) {
        send_bytes(parts[r], r);
        stats_.bytes_sent += parts[r].size();
        ++stats_.messages;
      }
      return parts[0];
    }
    Bytes b(mine);
    receive_bytes(b, 0);
    stats_.bytes_received += b.size();
    ++stats_.messages;
    return b;
  }

  std::vector<Bytes> gather(const Bytes& mine) override {
    const uint64_t n = mine.size();
    std::vector<uint64_t> sizes(rank_ == 0 ? size_ : 0);
    MPI_Request request;
    check(MPI_Igather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &request),
          "MPI_Igather");
    wait_politely(request, "MPI_Igather");
    if (rank_ != 0) {
      send_bytes(mine, 0);
      stats_.bytes_sent += mine.size();
      ++stats_.messages;
      return {};
    }
    std::vector<Bytes> all(size_);
    all[0] = mine;
    for (int r = 1; r < size_; ++r) {
      all[r].resize(sizes[r]);
      receive_bytes(all[r], r);
      stats_.bytes_received += sizes[r];
      ++stats_.messages;
    }
    return all;
  }

  [[noreturn]] void abort(int code) override {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::unique_ptr<Communicator> make_mpi_communicator(int& argc, char**& argv) {
  return std::make_unique<MpiCommunicator>(argc, argv);
}

void finalize_mpi() { MPI_Finalize(); }

}  // namespace trackassoc::distributed
