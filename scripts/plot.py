#!/usr/bin/python3
"""Plots for trackassoc's HDF5 results (Debian matplotlib, /usr/bin/python3).

One sub-command per plot kind; add yours as a function `plot_<kind>(args)` plus a sub-parser in
`main()`. Every sub-command reads an HDF5 file written by trackassoc and writes PNG files into
--outdir (created if needed), printing each path.

  plot.py seed002 seed002.h5 --outdir seed002-plots
      RMSE-per-time curves of `trackassoc experiment seed002`: for each motion, position, velocity
      and acceleration RMSE of the IMM (solid) and the CS-parallel filter (dash-dot), as the
      paper's Figs. 1-4, plus the mean IMM model probability.
  plot.py seed001 seed001.h5 --outdir seed001-plots
      seed 001 Fig. 3: (a) the system tracks of run 0 over the truth, (b) position RMSE per time of
      the proposed fuzzy association and FTAA.
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def _save(fig, outdir, name):
    os.makedirs(outdir, exist_ok=True)
    path = os.path.join(outdir, name)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    print(path)


def plot_seed002(args):
    titles = {"step": "acceleration step", "circle": "circle", "ca": "constant acceleration",
              "cv": "constant velocity"}
    rows = [("position", "m"), ("velocity", "m/s"), ("acceleration", "m/s²")]
    with h5py.File(args.file, "r") as f:
        group = f["seed002"]
        runs = f.attrs.get("runs", "?")
        for motion in group:
            g = group[motion]
            t = g["t"][:]
            imm, par = g["rmse_imm"][:], g["rmse_cs_parallel"][:]
            fig, axes = plt.subplots(4, 1, figsize=(7, 11), sharex=True)
            for q, (name, unit) in enumerate(rows):
                ax = axes[q]
                ax.plot(t, imm[q], "-", label="IMM {CS+network, CA}")
                ax.plot(t, par[q], "-.", label="CS-parallel")
                ax.set_ylabel(f"{name} RMSE [{unit}]")
                ratio = g.attrs.get(f"ratio_{name}", float("nan"))
                paper = g.attrs.get(f"paper_{name}", float("nan"))
                ax.set_title(f"{name}: ratio {ratio:.3f} (paper {paper:.3f})", fontsize=9)
                ax.grid(alpha=0.3)
                ax.legend(fontsize=8)
            axes[3].plot(t, g["imm_prob_cs"][:], color="k")
            axes[3].set_ylabel("mean μ(CS model)")
            axes[3].set_ylim(0, 1)
            axes[3].set_xlabel("time [s]")
            axes[3].grid(alpha=0.3)
            fig.suptitle(f"seed 002, {titles.get(motion, motion)} ({runs} runs)")
            _save(fig, args.outdir, f"seed002_{motion}.png")


def plot_seed001(args):
    """Seed 001 Fig. 3: (a) the association result of run 0, (b) position RMSE per time."""
    import numpy as np

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
        _save(fig, args.outdir, "seed001.png")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="kind", required=True)
    p = sub.add_parser("seed002", help="RMSE curves of `trackassoc experiment seed002`")
    p.add_argument("file")
    p.add_argument("--outdir", default="seed002-plots")
    p.set_defaults(func=plot_seed002)
    p = sub.add_parser("seed001", help="seed 001: association result of run 0 and RMSE per time (Fig. 3)")
    p.add_argument("file", help="HDF5 file written by `trackassoc experiment seed001`")
    p.add_argument("--outdir", default="seed001-plots")
    p.set_defaults(func=plot_seed001)
    args = parser.parse_args(argv)
    try:
        args.func(args)
    except (OSError, KeyError) as e:
        print(f"plot.py: error: {args.file}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
