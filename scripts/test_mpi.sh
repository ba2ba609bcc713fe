#!/usr/bin/env bash
# The MPI variant (docs/design.md §8; issue 19): set-up with OpenMPI, build build-mpi/ (-DTRACKASSOC_MPI=ON,
# the trackassoc binary only), then the MPI tests (ctest -L mpi: mpirun -np 2/3 --oversubscribe
# against one process, byte for byte; tests/mpi/mpi_case.sh). The default suite (scripts/test.sh)
# stays MPI-free.
set -euo pipefail
cd "$(dirname "$0")/.."
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
scripts/setup.sh --mpi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B build-mpi "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTRACKASSOC_MPI=ON \
  -DTRACKASSOC_BUILD_BENCH=OFF -DTRACKASSOC_BUILD_TESTS=OFF ${CMAKE_ARGS:-} >/dev/null
cmake --build build-mpi -j "$(nproc)" --target trackassoc
ctest --test-dir build-mpi -L mpi --output-on-failure --timeout 600 "$@"
