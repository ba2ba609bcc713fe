#!/usr/bin/env python3
"""How much a target's speed says across a gap in every sensor's coverage (docs/status.md, issue 29).

For each simulated track file (schema v1 with /tracks/truth, e.g. `trackassoc simulate --scenario
recorded_recycled --seed N`), the local tracks are cut into fragments of one target (sensor, track
number, truth: a recycled number gives two); a *transition* is a fragment's end that no other fragment
of its target covers, followed by that target's next fragment to start. Its rivals are the fragments of
other targets that start within WINDOW s after the end (stitching's candidates, docs/design.md §4.10).
Printed: the speed change |Δv| between the end's last state and the successor's state at its
START_REPORT-th report, for true transitions and for rivals, by gap length.

Usage: /usr/bin/python3 scripts/gap_transitions.py FILE.h5 [FILE.h5 ...]
"""
import sys

import h5py
import numpy as np

WINDOW = 180.0  # s, stitching's max_gap_s
START_REPORT = 5  # the successor's velocity after its first few reports (a new track's first is noisy)
MIN_REPORTS = 5


def fragments(path):
    with h5py.File(path, "r") as f:
        sensor, track = f["tracks/sensor"][:], f["tracks/track"][:]
        t, state, truth = f["tracks/t"][:], f["tracks/state"][:], f["tracks/truth"][:]
    order = np.lexsort((t, truth, track, sensor))
    key = np.stack([sensor[order], track[order], truth[order]], axis=1)
    cut = np.flatnonzero(np.any(key[1:] != key[:-1], axis=1)) + 1
    out = []
    for rows in np.split(order, cut):
        if truth[rows[0]] < 0 or len(rows) < MIN_REPORTS:
            continue  # a phantom, or too short for a velocity
        out.append({"target": int(truth[rows[0]]), "t0": t[rows[0]], "t1": t[rows[-1]],
                    "end": state[rows[-1]], "start": state[rows[min(START_REPORT, len(rows)) - 1]]})
    return out


def speed(x):
    half = len(x) // 2  # states are positions then velocities
    return float(np.linalg.norm(x[half:]))


def transitions(frags):
    true, rival = [], []
    by_target = {}
    for g in frags:
        by_target.setdefault(g["target"], []).append(g)
    for target, own in by_target.items():
        for e in own:
            if any(g is not e and g["t0"] <= e["t1"] < g["t1"] for g in own):
                continue  # another fragment of the target goes on: no gap in every sensor's coverage
            later = [g for g in own if g["t0"] > e["t1"]]
            if not later:
                continue
            succ = min(later, key=lambda g: g["t0"])
            true.append((succ["t0"] - e["t1"], abs(speed(e["end"]) - speed(succ["start"]))))
            for other, theirs in by_target.items():
                if other != target:
                    rival += [(g["t0"] - e["t1"], abs(speed(e["end"]) - speed(g["start"])))
                              for g in theirs if e["t1"] < g["t0"] <= e["t1"] + WINDOW]
    return true, rival


def main(paths):
    true, rival = [], []
    for p in paths:
        a, b = transitions(fragments(p))
        true += a
        rival += b
    if not true:
        sys.exit("no transition across a gap in every sensor's coverage")
    true, rival = np.array(true), np.array(rival)
    print(f"{len(paths)} files: {len(true)} true transitions, {len(rival)} rival starts")
    for name, r in (("true", true), ("rival", rival)):
        q = np.percentile(r[:, 1], [25, 50, 75])
        print(f"  {name:5s} |dv| quartiles {q[0]:.0f} / {q[1]:.0f} / {q[2]:.0f} m/s")
    for lo, hi in ((0, 30), (30, 60), (60, 100), (100, WINDOW)):
        m, mr = (true[:, 0] >= lo) & (true[:, 0] < hi), (rival[:, 0] >= lo) & (rival[:, 0] < hi)
        if m.any() and mr.any():
            p_true, p_rival = np.mean(true[m, 1] < 25), np.mean(rival[mr, 1] < 25)
            print(f"  gap {lo:3.0f}-{hi:3.0f} s: {m.sum():4d} true, P(|dv| < 25 m/s) {p_true:.2f} "
                  f"against {p_rival:.2f} for rivals")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
