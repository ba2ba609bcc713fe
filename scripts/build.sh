#!/usr/bin/env bash
# Set-up, then configure and build. Usage: scripts/build.sh [--sanitize] [--debug]
# Build folder: build/ (build-asan/ with --sanitize). Extra CMake flags via $CMAKE_ARGS.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (CMakeLists.txt uses it when present): paths relative to the checkout and no compile
# folder in the hash, so a clone in another folder reuses the objects of an earlier build.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"

build_dir=build
cmake_args=(-DCMAKE_BUILD_TYPE=Release)
for arg in "$@"; do
  case "$arg" in
    --sanitize) build_dir=build-asan
                cmake_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DTRACKASSOC_SANITIZE=ON -DTRACKASSOC_BUILD_BENCH=OFF) ;;
    --debug) build_dir=build-debug; cmake_args=(-DCMAKE_BUILD_TYPE=Debug) ;;
    *) echo "build.sh: unknown option $arg" >&2; exit 2 ;;
  esac
done

scripts/setup.sh
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B "$build_dir" "${generator[@]}" "${cmake_args[@]}" ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
echo "build: $build_dir ready"
