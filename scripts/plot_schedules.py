#!/usr/bin/python3
"""Gap vs wall time of `trackassoc experiment schedules` (issue 5 item 7).

Usage: plot_schedules.py SCHEDULES_H5 OUTPUT_PNG

One panel per family (seed 000 tracking instances: gap to the LR lower bound; DecompLib: gap to
the known optimum). Each method is one colour and marker; every point is one (instance, method)
run, its marker size growing with n. The y axis is symlog so that 0 % gaps stay visible. Reads
the HDF5 file the experiment writes (/schedules: one 1-D dataset per column, the method names as
the JSON attribute `methods`).
"""
import json
import sys


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    import h5py
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with h5py.File(argv[1], "r") as f:
        g = f["schedules"]
        methods = json.loads(g.attrs["methods"])
        col = {name: np.asarray(g[name][()]) for name in g}
    families = [("tracking", 0, "seed 000 tracking: gap to the LR lower bound"),
                ("decomplib", 1, "DecompLib: gap to the known optimum")]
    fig, axes = plt.subplots(1, 2, figsize=(14, 6), sharey=True)
    cmap = plt.get_cmap("tab20")
    markers = "os^vD<>phH*Xd8P"
    sizes = sorted(set(col["n"].tolist()))
    for ax, (family, flag, title) in zip(axes, families):
        in_family = col["decomplib"] == flag
        for m, name in enumerate(methods):
            sel = in_family & (col["method"] == m)
            if not sel.any():
                continue
            size = [12 + 60 * sizes.index(n) / max(1, len(sizes) - 1) for n in col["n"][sel]]
            ax.scatter(np.maximum(col["wall_time_s"][sel], 1e-6), 100 * col["gap"][sel], s=size,
                       color=cmap(m % 20), marker=markers[m % len(markers)], alpha=0.75,
                       label=name if family == "tracking" else None)
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=0.1)
        ax.set_xlabel("wall time [s] (marker size grows with n)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("gap [%] (symlog)")
    fig.legend(loc="center right", fontsize=8, frameon=False)
    fig.subplots_adjust(right=0.78, wspace=0.05)
    fig.savefig(argv[2], dpi=120)
    print(argv[2])


if __name__ == "__main__":
    main(sys.argv)
