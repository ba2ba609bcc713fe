#!/usr/bin/env python3
"""Log-log plot of `trackassoc experiment scale` (issue 6).

Usage: plot_scale.py SCALE_CSV OUTPUT_PNG

Left: wall time per stage and in total against targets per sensor, with n and n log n guides
through the largest size, and the dense path where it ran. Right: peak resident memory of the
sparse path (and the dense path) against n. Reads the CSV written by the experiment.
"""
import csv
import math
import sys


def read_rows(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if not r.get("error")]
    if not rows:
        sys.exit(f"plot_scale.py: {path} holds no successful rows")
    return rows


def column(rows, name):
    out = []
    for r in rows:
        v = r.get(name, "")
        out.append(float(v) if v not in ("", "nan") else math.nan)
    return out


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = read_rows(argv[1])
    n = column(rows, "n")
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(11, 4.5))
    for stage in ("alignment", "candidates", "statistics", "clusters", "solve"):
        ax_t.loglog(n, column(rows, f"{stage}_s"), "o-", ms=3, lw=1, label=stage)
    total = column(rows, "total_s")
    ax_t.loglog(n, total, "ks-", lw=2, label="sparse total")
    dense = column(rows, "dense_total_s")
    if any(not math.isnan(d) for d in dense):
        ax_t.loglog(n, dense, "r^--", lw=1.5, label="dense total")
    n_max, t_max = n[-1], total[-1]
    guide = [n[0], n_max]
    ax_t.loglog(guide, [t_max * x / n_max for x in guide], ":", color="grey", label="∝ n")
    ax_t.loglog(guide, [t_max * x * math.log(x) / (n_max * math.log(n_max)) for x in guide], "--", color="grey",
                label="∝ n log n")
    ax_t.loglog(guide, [t_max * (x / n_max) ** 2 for x in guide], "-.", color="lightgrey", label="∝ n²")
    ax_t.set_xlabel("targets (tracks) per sensor, 3 sensors")
    ax_t.set_ylabel("wall time [s]")
    ax_t.set_title("sparse association: time per stage")
    ax_t.grid(True, which="both", alpha=0.3)
    ax_t.legend(fontsize=7)
    ax_m.loglog(n, column(rows, "peak_mib"), "ks-", label="sparse peak RSS")
    dense_mem = column(rows, "dense_peak_mib")
    if any(not math.isnan(d) for d in dense_mem):
        ax_m.loglog(n, dense_mem, "r^--", label="dense peak RSS")
    ax_m.set_xlabel("targets (tracks) per sensor, 3 sensors")
    ax_m.set_ylabel("peak resident memory [MiB]")
    ax_m.set_title("peak memory (one process per size)")
    ax_m.grid(True, which="both", alpha=0.3)
    ax_m.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)


if __name__ == "__main__":
    main(sys.argv)
