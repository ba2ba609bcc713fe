#!/usr/bin/env bash
# Installs the Debian 12 packages trackassoc needs. Skips what is already installed; fails loudly.
# Usage: scripts/setup.sh [--binary] [--mpi]
# --binary: only what the `trackassoc` binary needs to build and run (scripts/demo.sh): compiler,
#   CMake, Ninja, Eigen, oneTBB, HDF5 (with zlib, which the PNG plots use), CLI11, nlohmann-json.
# default: also what scripts/test.sh, scripts/bench.sh and CI need: GoogleTest, Google Benchmark,
#   ccache, Debian's Python with numpy/h5py/scipy/matplotlib (plots of the studies, peers), clang
#   for the libFuzzer stage, Stone Soup's dependencies (the peer of `experiment recorded`), and
#   pybind11 with pytest and pandas for the Python module and its tests.
# --mpi: also OpenMPI (libopenmpi-dev, openmpi-bin) for the MPI build (scripts/test_mpi.sh,
#   docs/design.md §8); the default build and scripts/demo.sh, scripts/test.sh never need it.
set -euo pipefail
binary_only=0 with_mpi=0
for arg in "$@"; do
  case "$arg" in
    --binary) binary_only=1 ;;
    --mpi) with_mpi=1 ;;
    *) echo "setup.sh: unknown option $arg (expected --binary or --mpi)" >&2; exit 2 ;;
  esac
done

# The binary's packages (scripts/demo.sh installs these alone).
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libtbb-dev libhdf5-dev zlib1g-dev libcli11-dev nlohmann-json3-dev
)
if [ "$binary_only" -eq 0 ]; then
  packages+=(
    ccache libbenchmark-dev libgtest-dev libgmock-dev
    python3-h5py python3-numpy python3-matplotlib python3-scipy
    # libFuzzer targets of the CI fuzz stage (scripts/fuzz.sh)
    clang libclang-rt-14-dev
    # Stone Soup, the peer of `experiment recorded` (../shared/peers/stonesoup-src/README.md)
    python3-ordered-set python3-plotly python3-pymap3d python3-rtree python3-ruamel.yaml
    # the Python module (engine/python/, docs/design.md §9) and its pytest suite (tests/python/);
    # pandas for to_pandas() and the CSV round trip (optional to the module itself)
    pybind11-dev python3-pybind11 python3-dev python3-pytest python3-pandas
  )
fi
[ "$with_mpi" -eq 1 ] && packages+=(libopenmpi-dev openmpi-bin)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq || { echo "setup: apt-get update failed" >&2; exit 1; }
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" \
  || { echo "setup: apt-get install failed for: ${missing[*]}" >&2; exit 1; }
echo "setup: done"
