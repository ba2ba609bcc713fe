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
# Peers on the same inputs (python; each skips with a message when its package is missing):
# scipy's linear_sum_assignment on bench_lap's matrices, CBC on the Balas–Saltzman instances.
echo "== peers"
/usr/bin/python3 bench/lap_scipy.py --json bench-results/lap_scipy.json || echo "lap_scipy.py failed"
/usr/bin/python3 bench/cbc_3d.py --time-limit 300 --json bench-results/cbc_3d.json || echo "cbc_3d.py failed"
