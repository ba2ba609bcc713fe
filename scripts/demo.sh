#!/usr/bin/env bash
# Quick start 1: set-up, build, then run the main job on the embedded default scenario.
# Extra arguments go to `trackassoc run` (e.g. --threads 2 --seed 7).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
./build/trackassoc run "$@"
