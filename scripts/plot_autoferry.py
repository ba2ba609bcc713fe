#!/usr/bin/python3
"""One PNG per Autoferry scenario (issue 17 item 3): the lidar and radar detections in the Piren NED
frame, the local tracks coloured by their association target, and the GNSS truth.

Usage: /usr/bin/python3 scripts/plot_autoferry.py DATA_DIR OUT_DIR [--scenarios 2,3,...]
  DATA_DIR: the Autoferry data set (scenarioN/scenarioN_detections.json);
  OUT_DIR:  the folder of `trackassoc experiment autoferry --output OUT_DIR` (scenarioN.h5); the
            PNGs are written beside them as scenarioN.png.
Map axes: east to the right, north up. Colours: one per target number of the association
(/associations/<first>/target, else per tuple); grey = a local track in no tuple of two or more.
Lidar tracks solid, radar tracks dashed; truth black, one line per vessel.
"""
import argparse
import json
import os
import sys

try:
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:
    print(f"plot_autoferry: {e} (apt-get install python3-h5py python3-matplotlib)", file=sys.stderr)
    sys.exit(1)


def detections(path):
    """(sensor, north, east) arrays of the lidar (1) and radar (2) plots, in the Piren frame."""
    with open(path) as f:
        scans = json.load(f)
    out = {1: ([], []), 2: ([], [])}
    for s in scans:
        sid = s.get("sensorID")
        if sid not in out:
            continue
        m = s.get("measurement")
        if not m:
            continue
        own = s["ownshipPosition"]
        n, e = (m[0], m[1]) if isinstance(m[0], list) else ([m[0]], [m[1]])
        out[sid][0].extend(np.asarray(n, float) + own[0])
        out[sid][1].extend(np.asarray(e, float) + own[1])
    return out


def plot(data_dir, out_dir, n):
    h5 = os.path.join(out_dir, f"scenario{n}.h5")
    det = detections(os.path.join(data_dir, f"scenario{n}", f"scenario{n}_detections.json"))
    with h5py.File(h5, "r") as h:
        tr = h["tracks"]
        sensor, track, state = tr["sensor"][:], tr["track"][:], tr["state"][:]
        sensors = list(h["sensors"]["id"][:])
        colour_of = {}
        names = list(h["associations"].keys()) if "associations" in h else []
        if names:
            a = h["associations"][names[0]]
            tuples = a["tuples"][:]
            target = a["target"][:] if "target" in a else np.arange(len(tuples))
            for row, t in zip(tuples, target):
                if (row >= 0).sum() < 2:
                    continue
                for c, trk in enumerate(row):
                    if trk >= 0:
                        colour_of[(sensors[c], int(trk))] = int(t)
        truth = h["truth"] if "truth" in h else None
        fig, ax = plt.subplots(figsize=(8, 8))
        for sid, marker, label in ((1, ".", "lidar plots"), (2, "x", "radar plots")):
            ax.scatter(det[sid][1], det[sid][0], s=2, marker=marker, color="0.75", label=label, zorder=1)
        palette = plt.get_cmap("tab10")
        targets = sorted(set(colour_of.values()))
        for (sid, trk) in sorted(set(zip(sensor.tolist(), track.tolist()))):
            m = (sensor == sid) & (track == trk)
            t = colour_of.get((sid, trk))
            colour = "0.45" if t is None else palette(targets.index(t) % 10)
            ax.plot(state[m, 1], state[m, 0], "-" if sid == 1 else "--", color=colour, lw=2, zorder=3)
        if truth is not None:
            tid, ts = truth["target"][:], truth["state"][:]
            for v, style in zip(np.unique(tid), (":", "-.", (0, (1, 3)))):
                m = tid == v
                ax.plot(ts[m, 1], ts[m, 0], linestyle=style, color="black", lw=1, zorder=2,
                        label=f"truth vessel {v}")
        ax.plot([], [], "-", color="0.2", label="lidar track")
        ax.plot([], [], "--", color="0.2", label="radar track")
        ax.set_xlabel("east [m] (Piren)")
        ax.set_ylabel("north [m] (Piren)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"Autoferry scenario {n}: tracks coloured by association target")
        ax.legend(loc="best", fontsize=8)
        png = os.path.join(out_dir, f"scenario{n}.png")
        fig.savefig(png, dpi=110, bbox_inches="tight")
        plt.close(fig)
    return png


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("data_dir")
    p.add_argument("out_dir")
    p.add_argument("--scenarios", default="2,3,4,5,6,13,16,17,22")
    a = p.parse_args()
    for n in a.scenarios.split(","):
        print(plot(a.data_dir, a.out_dir, int(n)))


if __name__ == "__main__":
    main()
