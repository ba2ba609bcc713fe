#!/usr/bin/env bash
# Quick start 1: set-up with the binary's packages only, build the `trackassoc` binary alone
# (scripts/build.sh --binary: no tests, no benchmarks), then run the main job on the embedded
# default scenario: the table on the terminal, trackassoc-run.h5, and the pictures
# trackassoc-run.png (the recording as a map) and trackassoc-run-summary.png (every solver).
# Extra arguments go to `trackassoc run` (e.g. --threads 2 --seed 7, --svg).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh --binary
./build/trackassoc run "$@"
