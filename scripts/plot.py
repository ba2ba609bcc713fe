#!/usr/bin/python3
"""Plots of trackassoc results, one sub-command per study. Reads the HDF5 files directly (h5py).

    /usr/bin/python3 scripts/plot.py seed001 seed001.h5 --out plots/

Add a sub-command per experiment: a function plot_<name>(args) and a parser entry in main().
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_seed001(args):
    """Seed 001 Fig. 3: (a) the association result of run 0, (b) position RMSE per time."""
    os.makedirs(args.out, exist_ok=True)
    with h5py.File(args.file, "r") as f:
        fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
        ax = axes[0]
        if "truth" in f:
            target = f["truth/target"][:]
            state = f["truth/state"][:]
            for k in np.unique(target):
                sel = target == k
                ax.plot(state[sel, 0] / 1e3, state[sel, 1] / 1e3, "k-", lw=1, label="truth" if k == target.min() else None)
        for name, marker in (("fuzzy", "o"), ("ftaa", "x")):
            grp = f.get("system_tracks/" + name)
            if grp is None:
                continue
            track = grp["track"][:]
            state = grp["state"][:]
            for j in np.unique(track):
                sel = track == j
                ax.plot(state[sel, 0] / 1e3, state[sel, 1] / 1e3, marker, ms=2.5, alpha=0.6,
                        label="%s system track %d" % (name, j))
        ax.set_xlabel("x [km]")
        ax.set_ylabel("y [km]")
        ax.set_title("(a) association result, run 0")
        ax.legend(fontsize=7, loc="best")
        ax.axis("equal")

        ax = axes[1]
        for name, style in (("fuzzy", "-"), ("ftaa", "--")):
            grp = f.get("metrics/seed001_" + name)
            if grp is None:
                continue
            t = grp["time"][:]
            for k in (0, 1):
                ax.plot(t, grp["rmse_target%d" % k][:], style, lw=1,
                        label="%s S%d (mean %.1f m)" % ("proposed" if name == "fuzzy" else "FTAA", k + 1,
                                                      grp["mean_rmse"][k]))
        ax.set_xlabel("t [s]")
        ax.set_ylabel("position RMSE [m]")
        ax.set_yscale("log")
        ax.set_title("(b) position RMSE over the Monte Carlo runs")
        ax.legend(fontsize=8)
        fig.tight_layout()
        path = os.path.join(args.out, "seed001.png")
        fig.savefig(path, dpi=120)
        print("wrote", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("seed001", help="seed 001: association result and RMSE per time (Fig. 3)")
    p.add_argument("file", help="HDF5 file written by `trackassoc experiment seed001`")
    p.add_argument("--out", default=".", help="output folder")
    p.set_defaults(func=plot_seed001)
    args = parser.parse_args()
    args.func(args)


if __name__ == "__main__":
    sys.exit(main())
