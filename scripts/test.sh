#!/usr/bin/env bash
# Quick start 2: set-up with every package (scripts/setup.sh), build everything (the binary, the
# test programs and the benchmarks), then run the test suite with ctest.
# --sanitize: the same suite under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build
[ "${1:-}" = "--sanitize" ] && build_dir=build-asan
scripts/build.sh "$@"
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" --timeout 600
