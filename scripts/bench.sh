#!/usr/bin/env bash
# One benchmark run: every Google Benchmark program (1 and 2 threads where the kernel is parallel),
# then every peer on the same inputs, then the performance table of docs/performance.md with the ratios
# (scripts/bench_report.py). Everything lands in bench-results/: <program>.json, the peers' JSON,
# meta.txt (machine, load before and after), report.md (the table).
# Usage: scripts/bench.sh [FILTER_REGEX]   (passed as --benchmark_filter; the peers run only
#        without a filter, since their ratios need the whole set)
# Takes about an hour on the 2-core machine (CBC on the 60 DecompLib instances is ~half of it).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh
mkdir -p bench-results
filter="${1:-.}"
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') × $(nproc)"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} > bench-results/meta.txt
for b in build/bench_*; do
  [ -x "$b" ] || continue
  name=$(basename "$b")
  echo "== $name"
  echo "load before $name: $(cut -d' ' -f1-3 /proc/loadavg)" >> bench-results/meta.txt
  "$b" --benchmark_filter="$filter" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
       --benchmark_out="bench-results/$name.json" --benchmark_out_format=json
done
echo "load after the programs: $(cut -d' ' -f1-3 /proc/loadavg)" >> bench-results/meta.txt
if [ "$filter" != "." ]; then
  echo "bench.sh: filter given; peers and the report skipped"
  exit 0
fi
# Peers on the same inputs (Debian's python; each skips with a message when its package is missing).
py=/usr/bin/python3
echo "== peers"
# scipy's linear_sum_assignment on bench_lap's matrices.
$py bench/lap_scipy.py --json bench-results/lap_scipy.json || echo "lap_scipy.py failed"
# CBC (one thread) on the DecompLib and Balas–Saltzman instances of bench_3d_solvers; its log also
# gives the LP relaxation's bound and time (the Lagrangian relaxation's peer).
$py bench/cbc_3d.py --set decomplib --ours bench-results/bench_3d_solvers.json \
    --json bench-results/cbc_decomplib.json || echo "cbc_3d.py decomplib failed"
$py bench/cbc_3d.py --set balas-saltzman --json bench-results/cbc_balas_saltzman.json \
    || echo "cbc_3d.py balas-saltzman failed"
# Stone Soup's track-to-track associator on the file of bench_recorded's recorded_sync case (as
# shipped: the file is synchronous, the resampled runs are not timed here).
build/trackassoc simulate --scenario recorded_sync --seed 1 -o bench-results/recorded_sync.h5 > /dev/null
for r in 1 2 3; do
  $py bench/stonesoup_t2t.py bench-results/recorded_sync.h5 --cov sum --no-resampled \
      --json "bench-results/stonesoup_recorded_sync_$r.json" > /dev/null || echo "stonesoup_t2t.py failed"
done
# Stone Soup's TrackStitcher beside our fragment stitching on the same fragments (the groups of
# `associate --no-stitch`) of recorded_recycled, seeds 1-3: joins, correct, false, time (ours: the
# stitching stage of `associate`). bench/stonesoup_stitch.py.
for s in 1 2 3; do
  in=bench-results/recorded_recycled_$s.h5
  build/trackassoc simulate --scenario recorded_recycled --seed $s -o "$in" > /dev/null
  build/trackassoc associate -i "$in" -o "bench-results/recycled_fragments_$s.h5" --no-stitch > /dev/null
  ms=$(build/trackassoc associate -i "$in" -o "bench-results/recycled_ours_$s.h5" |
       grep -o 'stitching [0-9.]* ms' | cut -d' ' -f2)
  $py bench/stonesoup_stitch.py "bench-results/recycled_fragments_$s.h5" "bench-results/recycled_ours_$s.h5" \
      --ours-ms "${ms:-0}" --json "bench-results/stonesoup_stitch_recycled_$s.json" || echo "stonesoup_stitch.py failed"
done
# The same on widearea_small (issue 31 item 3): its first 600 s (TrackStitcher steps through every
# second of the 2-hour file; the fragments that end by 600 s, ~7 min), ours over the whole file.
in=bench-results/widearea_small.h5
build/trackassoc simulate --scenario widearea_small --seed 1 -o "$in" > /dev/null
build/trackassoc associate -i "$in" -o bench-results/widearea_small_fragments.h5 --no-stitch > /dev/null
ms=$(build/trackassoc associate -i "$in" -o bench-results/widearea_small_ours.h5 |
     grep -o 'stitching [0-9.]* ms' | cut -d' ' -f2)
$py bench/stonesoup_stitch.py bench-results/widearea_small_fragments.h5 bench-results/widearea_small_ours.h5 \
    --ours-ms "${ms:-0}" --until 600 --json bench-results/stonesoup_stitch_widearea_small.json \
    || echo "stonesoup_stitch.py failed"
# numpy's loadtxt on bench_csv_import's file.
$py bench/csv_numpy.py --json bench-results/csv_numpy.json || echo "csv_numpy.py failed"
echo "load after the peers: $(cut -d' ' -f1-3 /proc/loadavg)" >> bench-results/meta.txt
echo "== report"
$py scripts/bench_report.py bench-results | tee bench-results/report.md
