#!/usr/bin/env bash
# Set-up, then configure and build. Usage: scripts/build.sh [--binary] [--sanitize] [--debug]
# --binary: the `trackassoc` binary alone, with only its packages (scripts/setup.sh --binary), no
#   GoogleTest, Google Benchmark or the Python module (scripts/demo.sh). Default: everything (tests,
#   benchmarks, the Python module when pybind11 is installed).
# Build folder: build/ (build-asan/ with --sanitize). Extra CMake flags via $CMAKE_ARGS.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (CMakeLists.txt uses it when present): paths relative to the checkout and no compile
# folder in the hash, so a clone in another folder reuses the objects of an earlier build.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"

build_dir=build
binary_only=0
build_type=(-DCMAKE_BUILD_TYPE=Release)
bench=ON
extra=()
for arg in "$@"; do
  case "$arg" in
    --binary) binary_only=1 ;;
    --sanitize) build_dir=build-asan
                build_type=(-DCMAKE_BUILD_TYPE=RelWithDebInfo)
                extra=(-DTRACKASSOC_SANITIZE=ON)
                bench=OFF ;;
    --debug) build_dir=build-debug; build_type=(-DCMAKE_BUILD_TYPE=Debug) ;;
    *) echo "build.sh: unknown option $arg" >&2; exit 2 ;;
  esac
done

if [ "$binary_only" -eq 1 ]; then
  scripts/setup.sh --binary
  parts=(-DTRACKASSOC_BUILD_TESTS=OFF -DTRACKASSOC_BUILD_BENCH=OFF -DTRACKASSOC_PYTHON=OFF)
  targets=(--target trackassoc)
else
  scripts/setup.sh
  parts=(-DTRACKASSOC_BUILD_TESTS=ON "-DTRACKASSOC_BUILD_BENCH=$bench" -DTRACKASSOC_PYTHON=ON)
  targets=()
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B "$build_dir" "${generator[@]}" "${build_type[@]}" "${extra[@]}" "${parts[@]}" ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
echo "build: $build_dir ready"
