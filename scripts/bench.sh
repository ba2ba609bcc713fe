#!/usr/bin/env bash
# Builds and runs every Google Benchmark program, writing JSON to bench-results/<name>.json.
# Usage: scripts/bench.sh [FILTER_REGEX]   (passed as --benchmark_filter)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p bench-results
filter="${1:-.}"
for b in build/bench_*; do
  [ -x "$b" ] || continue
  name=$(basename "$b")
  echo "== $name"
  "$b" --benchmark_filter="$filter" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
       --benchmark_out="bench-results/$name.json" --benchmark_out_format=json
done
