#!/usr/bin/env bash
# Installs the Debian 12 packages trackassoc needs. Skips what is already installed; fails loudly.
# --mpi: also OpenMPI (libopenmpi-dev, openmpi-bin) for the MPI build (scripts/test_mpi.sh,
# DESIGN §8); the default build and scripts/demo.sh, scripts/test.sh never need it.
set -euo pipefail
with_mpi=0
for arg in "$@"; do
  case "$arg" in
    --mpi) with_mpi=1 ;;
    *) echo "setup.sh: unknown option $arg (expected --mpi)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libtbb-dev libhdf5-dev libbenchmark-dev libgtest-dev libgmock-dev
  libcli11-dev nlohmann-json3-dev
  python3-h5py python3-numpy python3-matplotlib python3-scipy
  # libFuzzer targets of the CI fuzz stage (scripts/fuzz.sh)
  clang libclang-rt-14-dev
  # Stone Soup, the peer of `experiment recorded` (../shared/peers/stonesoup-src/README.md)
  python3-ordered-set python3-plotly python3-pymap3d python3-rtree python3-ruamel.yaml
  # the Python module (engine/python/, DESIGN §9) and its pytest suite (tests/python/); pandas
  # for to_pandas() and the CSV round trip (optional to the module itself)
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-pandas
)
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
