#!/usr/bin/env python3
"""Log-log plot of `trackassoc experiment scale` (issue 6).

Usage: plot_scale.py SCALE_H5|SCALE_CSV OUTPUT_PNG

Left: wall time per stage and in total against targets per sensor, with n and n log n guides
through the largest size, and the dense path where it ran. Right: peak resident memory of the
sparse path (and the dense path) against n. Reads the HDF5 file written by the experiment
(/scale/..., layout in engine/studies/scale/experiment_scale.hpp; needs h5py, e.g. /usr/bin/python3 on Debian)
or, for files of older runs, its CSV.
"""
import csv
import math
import sys

STAGES = ("alignment", "candidates", "statistics", "components", "solve")


def read_rows(path):
    """Successful rows as dicts of column name -> value (CSV column names)."""
    if path.endswith(".csv"):
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if not r.get("error")]
    else:
        import h5py
        with h5py.File(path, "r") as f:
            g = f["scale"]
            stages = g.attrs["stages"]
            stages = (stages.decode() if isinstance(stages, bytes) else stages).split(",")
            rows = []
            for k in range(g["n"].shape[0]):
                if not g["ok"][k]:
                    continue
                r = {"n": g["n"][k]}
                for name in ("total_s", "peak_mib", "dense_total_s", "dense_peak_mib"):
                    r[name] = g[name][k]
                for q, stage in enumerate(stages):
                    r[f"{stage}_s"] = g["stage_s"][k, q]
                rows.append(r)
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
    for stage in STAGES:
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
