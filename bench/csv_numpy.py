#!/usr/bin/python3
"""Peer of bench_csv_import: numpy.loadtxt on the same 10^6-row CSV (bench_csv_import writes it
once into the temporary folder as trackassoc_bench_csv_0.csv: t, sensor, track, x, y, vx, vy).

numpy's loadtxt (C parser since numpy 1.23) only parses the numbers into one float array: what a
user's script does before it can group rows into tracks. `trackassoc import csv` (BM_ImportCsv/0)
also maps the columns, validates every field, groups the rows per (sensor, track), sorts each track
in time and fills the covariances, so the ratio understates the work per row on our side.

Usage: /usr/bin/python3 bench/csv_numpy.py [CSV] [--repetitions 5] [--json OUT]
Skips with a message (exit 0) if the file or numpy is missing: it is a benchmark peer.
"""
import argparse
import json
import os
import statistics
import sys
import tempfile
import time


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", nargs="?", default=os.path.join(tempfile.gettempdir(), "trackassoc_bench_csv_0.csv"))
    p.add_argument("--repetitions", type=int, default=5)
    p.add_argument("--json", help="write the results here")
    args = p.parse_args()
    try:
        import numpy as np
    except ImportError:
        print("csv_numpy: numpy not installed (apt-get install python3-numpy); skipping")
        return 0
    if not os.path.exists(args.csv):
        print(f"csv_numpy: {args.csv} not found (run build/bench_csv_import first); skipping")
        return 0
    times, rows = [], 0
    for _ in range(args.repetitions):
        t0 = time.perf_counter()
        a = np.loadtxt(args.csv, delimiter=",", skiprows=1, dtype=np.float64)
        times.append(time.perf_counter() - t0)
        rows = a.shape[0]
    med = statistics.median(times)
    print(f"numpy {np.__version__} loadtxt: {rows} rows, median {med:.3f} s of {args.repetitions} "
          f"({rows / med / 1e6:.2f} M rows/s)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"peer": f"numpy {np.__version__} loadtxt", "file": args.csv, "rows": rows,
                       "median_s": med, "times_s": times}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
