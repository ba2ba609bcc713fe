#!/usr/bin/python3
"""Peer comparison: Stone Soup's TrackStitcher beside trackassoc's fragment stitching.

What it does
    Both join the same fragments: the output groups (local tracks of one target number) of
    `trackassoc associate --no-stitch` on a schema-v1 file (FRAGMENTS.h5). Ours is the default
    `associate` (OURS.h5), whose stitching stage (engine/pipeline/track_stitching.hpp) works on those
    groups and writes the joins into /associations/NAME/target. Stone Soup's TrackStitcher
    (stonesoup/stitcher.py: forward and backward prediction of track ends, then scipy's
    linear_sum_assignment) gets one Track per group: the group's reports in time order as
    GaussianStates (one per timestamp), as its Track_Stitching example sets it up:
      transition  CombinedLinearGaussianTransitionModel([ConstantVelocity(q)] * d),
      hypothesisers  DistanceHypothesiser(KalmanPredictor, KalmanUpdater(measurement model None),
                     Mahalanobis(), missed_distance = sqrt(chi2_D(0.9999))), forward and backward,
      search_window  --window s (default 180 s, our max_gap_s).
    A join is two groups of one stitched track that follow each other in time. Reported for each
    side: joins made, correct (both groups' majority truth the same target, >= 0), false, the
    true joins available (consecutive fragments of one target that start within the window of
    the previous one's end), and the time (Stone Soup's stitch() call; ours: the stitching stage
    of `associate`, given with --ours-ms, or not reported).

How to run (from the repo root, Debian's Python, as bench/stonesoup_t2t.py):
    build/trackassoc associate -i IN.h5 -o FRAG.h5 --no-stitch
    build/trackassoc associate -i IN.h5 -o OURS.h5
    /usr/bin/python3 bench/stonesoup_stitch.py FRAG.h5 OURS.h5 [--name NAME] [--q 9]
        [--window 180] [--until SECONDS] [--json OUT.json]
    Exit status: 0 ok, 2 bad input, 3 Stone Soup (or a dependency) cannot be imported.

Caveats
    * TrackStitcher steps through every second of the recording and, per second, hypothesises
      each track that ended within the window against the starts of that second: its time grows
      with (span in seconds) x (tracks ending per window), fine for the recorded family's 300 s.
    * Its backward prediction runs Stone Soup's KalmanPredictor with a negative interval, as its
      example does; ConstantVelocity's covariance uses |dt|.
"""
import argparse
import json
import os
import sys
import time
from collections import Counter, defaultdict
from datetime import datetime, timedelta

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stonesoup_t2t as t2t  # noqa: E402  (bench/, beside this script: load, layouts, Stone Soup path)

EPOCH = datetime(2000, 1, 1)


def import_stitcher():
    src = os.environ.get("STONESOUP_SRC", os.path.join(t2t.REPO, "..", "shared", "peers", "stonesoup-src"))
    sys.path[:0] = [os.path.abspath(src), os.path.abspath(os.path.join(src, "stub"))]
    try:
        from scipy.stats import chi2
        from stonesoup.hypothesiser.distance import DistanceHypothesiser
        from stonesoup.measures import Mahalanobis
        from stonesoup.models.transition.linear import (CombinedLinearGaussianTransitionModel,
                                                        ConstantVelocity)
        from stonesoup.predictor.kalman import KalmanPredictor
        from stonesoup.stitcher import TrackStitcher
        from stonesoup.types.state import GaussianState
        from stonesoup.types.track import Track
        from stonesoup.updater.kalman import KalmanUpdater
    except ImportError as e:
        print(f"stonesoup_stitch: cannot import module '{e.name}' (STONESOUP_SRC={src})", file=sys.stderr)
        sys.exit(3)
    return locals()


def groups_of(path, name):
    """{target number: [(sensor id, track)]} of /associations/NAME (the only one when NAME is None;
    tuple columns = /sensors order)."""
    import h5py
    with h5py.File(path, "r") as f:
        ids = [int(s) for s in f["sensors/id"][()]]
        names = list(f["associations"].keys())
        if name is None and len(names) != 1:
            raise ValueError(f"{path}: give --name, /associations holds {names}")
        a = f["associations"][name or names[0]]
        tuples = a["tuples"][()]
        target = a["target"][()] if "target" in a else np.arange(len(tuples))
    out = defaultdict(list)
    for k, row in enumerate(tuples):
        for c, trk in enumerate(row):
            if trk >= 0:
                out[int(target[k])].append((ids[c], int(trk)))
    return out


def score(chains, truth):
    """Joins of the chains (each a list of fragments in time order: consecutive ones are a join),
    correct when both fragments' truth is one target (>= 0), false otherwise."""
    joins = [(p, n) for chain in chains for p, n in zip(chain, chain[1:])]
    correct = sum(1 for p, n in joins if truth[p] == truth[n] >= 0)
    return dict(joins=len(joins), correct=correct, false=len(joins) - correct)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("fragments", help="associate --no-stitch output")
    ap.add_argument("ours", help="associate (default) output of the same input")
    ap.add_argument("--name", default=None, help="the association (default: the only one)")
    ap.add_argument("--q", type=float, default=9.0, help="ConstantVelocity noise diff coeff [m^2/s^3]")
    ap.add_argument("--window", type=float, default=180.0, help="search window [s]")
    ap.add_argument("--ours-ms", type=float, default=None, help="our stitching stage's time [ms]")
    ap.add_argument("--until", type=float, default=None,
                    help="only the fragments that end by this time [s] (both sides scored on their joins "
                         "among them; for recordings of hours, which TrackStitcher steps through second by second)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    try:
        d = t2t.load(a.fragments)
        frag = groups_of(a.fragments, a.name)
        ours = groups_of(a.ours, a.name)
    except (OSError, KeyError, ValueError) as e:
        print(f"stonesoup_stitch: {e}", file=sys.stderr)
        return 2
    ss = import_stitcher()
    perm, _ = t2t.LAYOUTS[d["layout"]]
    dim = len(perm)
    iu = np.triu_indices(dim)
    rows_of = defaultdict(list)
    for r, key in enumerate(zip(d["sensor"].tolist(), d["track"].tolist())):
        rows_of[key].append(r)
    # Each fragment: its rows in time order, one per timestamp; its majority truth.
    tracks, truth, span = {}, {}, {}
    for g, keys in frag.items():
        rows = sorted((r for k in keys for r in rows_of[k]), key=lambda r: d["t"][r])
        states, last_t = [], None
        for r in rows:
            if last_t is not None and d["t"][r] == last_t:
                continue
            last_t = d["t"][r]
            P = np.zeros((dim, dim))
            P[iu] = d["cov"][r]
            P = P + np.triu(P, 1).T
            x = d["state"][r][perm]
            states.append(ss["GaussianState"](x.reshape(-1, 1), P[np.ix_(perm, perm)],
                                              timestamp=EPOCH + timedelta(seconds=float(last_t))))
        tracks[g] = ss["Track"](states, id=str(g))
        votes = Counter(int(d["truth"][r]) for r in rows)
        good = sorted((-n, t) for t, n in votes.items() if t >= 0)
        truth[g] = good[0][1] if good else -1
        span[g] = (d["t"][rows[0]], d["t"][rows[-1]])
    if a.until is not None:  # the fragments inside [start, until]; ours keeps its joins among them
        keep = {g for g in tracks if span[g][1] <= a.until}
        tracks = {g: tracks[g] for g in keep}
        truth = {g: truth[g] for g in keep}
    # True joins available: consecutive fragments of one target within the window.
    by_truth = defaultdict(list)
    for g, t in truth.items():
        if t >= 0:
            by_truth[t].append(g)
    available = 0
    for gs in by_truth.values():
        gs.sort(key=lambda g: span[g][0])
        available += sum(1 for p, n in zip(gs, gs[1:]) if span[n][0] - span[p][1] <= a.window)

    # Ours: fragments whose keys share a target number in OURS.h5, in time order.
    target_of = {k: t for t, keys in ours.items() for k in keys}
    merged = defaultdict(list)
    for g, keys in frag.items():
        merged[target_of.get(keys[0], ("alone", g))].append(g)
    ours_chains = [sorted(gs, key=lambda g: span[g][0]) for gs in merged.values() if len(gs) > 1]
    if a.until is not None:  # its joins with both fragments kept, each a chain of two
        ours_chains = [[p, n] for c in ours_chains for p, n in zip(c, c[1:]) if p in tracks and n in tracks]
    # Stone Soup.
    model = ss["CombinedLinearGaussianTransitionModel"]([ss["ConstantVelocity"](a.q)] * (dim // 2))
    gate = float(np.sqrt(ss["chi2"].ppf(0.9999, dim)))

    def hyp():
        return ss["DistanceHypothesiser"](ss["KalmanPredictor"](model), ss["KalmanUpdater"](None),
                                          ss["Mahalanobis"](), missed_distance=gate)
    stitcher = ss["TrackStitcher"](forward_hypothesiser=hyp(), backward_hypothesiser=hyp(),
                                   search_window=timedelta(seconds=a.window))
    t0 = time.perf_counter()
    _, stitched = stitcher.stitch(set(tracks.values()), EPOCH)
    ss_s = time.perf_counter() - t0
    ss_chains = [[int(i) for i in ids] for ids in stitched.values() if len(ids) > 1]
    out = dict(file=a.fragments, until_s=a.until, fragments=len(tracks), true_joins_available=available,
               ours=dict(score(ours_chains, truth), ms=a.ours_ms),
               stonesoup=dict(score(ss_chains, truth), ms=1e3 * ss_s))
    until = "" if a.until is None else f" ending by {a.until:g} s"
    print(f"{a.fragments}: {len(tracks)} fragments{until}, {available} true joins available")
    for side in ("ours", "stonesoup"):
        s = out[side]
        ms = "" if s["ms"] is None else f", {s['ms']:.1f} ms"
        print(f"  {side:10s} joins {s['joins']:3d}  correct {s['correct']:3d}  false {s['false']:3d}{ms}")
    if a.json:
        with open(a.json + ".tmp", "w") as f:
            json.dump(out, f, indent=1)
        os.replace(a.json + ".tmp", a.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
