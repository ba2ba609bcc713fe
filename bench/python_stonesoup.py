#!/usr/bin/python3
"""The Python module against Stone Soup and against the command line, measured in one run (issue 32;
docs/python.md).

1. Stone Soup users: the same Stone Soup Track objects (GaussianState, built from a simulated file by
   bench/stonesoup_t2t.py, as `experiment recorded` runs the peer) associated by
     - trackassoc.stonesoup.TrackToTrackAssociator().associate_tracks(*sets): all sensors at once,
       time including the conversion of the Track objects to arrays;
     - Stone Soup's OneToOneTrackAssociator (MeanMeasure(StateSequenceMeasure(SquaredMahalanobis())),
       threshold chi2_D(0.99)), pairwise chained over the sensors (bench/stonesoup_t2t.py), as
       shipped (the first track's covariance) and with P1 + P2 (--cov sum there); its time is that
       of its associate_tracks calls;
   correct rate by the project's rule (bench/stonesoup_t2t.py score), time = median of --repeat runs
   (Stone Soup: of --peer-repeat runs).
2. Module against CLI on the same file: `trackassoc associate --input F --output O` (wall time of the
   process) against read + associate + write in Python (wall time in the interpreter), medians of
   --repeat runs, alternating; and the engine's own association time (the record's runtime_s) of each.

Run from the repo root after scripts/build.sh (Debian's Python; Stone Soup from ../shared/peers):
    /usr/bin/python3 bench/python_stonesoup.py [--seed 1] [--repeat 5] [--peer-repeat 3] [--json OUT]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "build", "python"))
sys.path.insert(0, os.path.join(REPO, "bench"))
CLI = os.path.join(REPO, "build", "trackassoc")


def simulate(folder, scenario, seed):
    path = os.path.join(folder, "%s-%d.h5" % (scenario, seed))
    subprocess.run([CLI, "simulate", "--scenario", scenario, "--seed", str(seed), "--output", path], check=True,
                   capture_output=True)
    return path


def key_tuples(association_set, tracks, num_sensors):
    """Our AssociationSet as the bench's K x S tuples (the extra segments of a sensor as tuples of their own)."""
    import numpy as np
    key_of = {id(t): k for k, t in tracks.items()}
    rows, seen = [], set()
    for a in association_set.associations:
        row = np.full(num_sensors, -1, np.int32)
        for k in sorted(key_of[id(t)] for t in a.objects):
            seen.add(k)
            if row[k[0]] < 0:
                row[k[0]] = k[1]
            else:
                extra = np.full(num_sensors, -1, np.int32)
                extra[k[0]] = k[1]
                rows.append(extra)
        rows.append(row)
    for k in tracks:
        if k not in seen:
            row = np.full(num_sensors, -1, np.int32)
            row[k[0]] = k[1]
            rows.append(row)
    return np.array(rows)


def stonesoup_rows(path, repeat, peer_repeat):
    import stonesoup_t2t as bench
    from trackassoc.stonesoup import TrackToTrackAssociator
    ss = bench.import_stonesoup()
    d = bench.load(path)
    tracks, times = bench.build_tracks(d, ss)
    S = len(d["sensors"])
    sets = [[tracks[k] for k in sorted(tracks) if k[0] == c] for c in range(S)]
    truth_of = bench.track_truths(d)
    ours_t, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = TrackToTrackAssociator().associate_tracks(*sets)
        ours_t.append(time.perf_counter() - t0)
    ours = bench.score(key_tuples(result, tracks, S), truth_of)
    threshold = float(ss["chi2"].ppf(0.99, d["state"].shape[1]))
    row = dict(tracks=len(tracks), states=int(len(d["t"])), targets=ours["targets"],
               ours=dict(correct_rate=ours["correct_rate"], false_rate=ours["false_rate"],
                         linked=ours["linked_tuples"], time_s=statistics.median(ours_t), times=ours_t))
    # The peer as shipped (SquaredMahalanobis: the first track's covariance) and with P1 + P2 (the
    # textbook statistic, as `experiment recorded` and the Performance table run it). Its time is
    # that of its associate_tracks calls alone (run_chained's assoc_time), not of the chaining.
    for cov in ("first", "sum"):
        peer_t, peer = [], None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for _ in range(peer_repeat):
                tuples, assoc_time, _ = bench.run_chained(tracks, times, S,
                                                          bench.make_one2one(ss, tracks, threshold, cov))
                peer_t.append(assoc_time)
                peer = bench.score(tuples, truth_of)
        row["stonesoup_" + cov] = dict(correct_rate=peer["correct_rate"], false_rate=peer["false_rate"],
                                       linked=peer["linked_tuples"], time_s=statistics.median(peer_t), times=peer_t)
    return row


def module_vs_cli(path, folder, repeat):
    import trackassoc
    cli_t, mod_t, cli_engine, mod_engine = [], [], [], []
    out_cli, out_mod = os.path.join(folder, "cli.h5"), os.path.join(folder, "module.h5")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run([CLI, "associate", "--input", path, "--output", out_cli], check=True, capture_output=True)
        cli_t.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        f = trackassoc.read(path)
        a = trackassoc.associate(f)
        trackassoc.write(out_mod, f, associations=[a])
        mod_t.append(time.perf_counter() - t0)
        cli_engine.append(next(iter(trackassoc.read(out_cli).associations.values())).summary["runtime_s"])
        mod_engine.append(a.summary["runtime_s"])
    same = (trackassoc.read(out_cli).associations["lr+ls"].tuples.tobytes() == a.tuples.tobytes())
    return dict(cli_s=statistics.median(cli_t), module_s=statistics.median(mod_t),
                cli_engine_s=statistics.median(cli_engine), module_engine_s=statistics.median(mod_engine),
                same_tuples=same, cli_times=cli_t, module_times=mod_t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--peer-repeat", type=int, default=3)
    ap.add_argument("--json")
    args = ap.parse_args()
    out = {}
    with tempfile.TemporaryDirectory() as folder:
        for scenario in ("recorded_sync", "recorded_3s"):
            path = simulate(folder, scenario, args.seed)
            r = stonesoup_rows(path, args.repeat, args.peer_repeat)
            out[scenario] = r
            o = r["ours"]
            print("%-14s %d tracks, %d states, %d targets | ours: %.1f%% correct, %.1f ms" % (
                scenario, r["tracks"], r["states"], r["targets"], 100 * o["correct_rate"], 1e3 * o["time_s"]))
            for cov in ("first", "sum"):
                p = r["stonesoup_" + cov]
                print("    Stone Soup OneToOne (%s): %.1f%% correct, %d linked tuples, %.1f ms, %.1fx ours" % (
                    "as shipped" if cov == "first" else "P1+P2", 100 * p["correct_rate"], p["linked"],
                    1e3 * p["time_s"], p["time_s"] / o["time_s"]))
        for scenario in ("recorded_sync", "recorded_5s"):
            path = simulate(folder, scenario, args.seed)
            m = module_vs_cli(path, folder, args.repeat)
            out["module_vs_cli_" + scenario] = m
            print("%-14s CLI associate %.1f ms (engine %.1f ms) | module read+associate+write %.1f ms (engine "
                  "%.1f ms) | module/CLI %.3f, same tuples %s" % (
                      scenario, 1e3 * m["cli_s"], 1e3 * m["cli_engine_s"], 1e3 * m["module_s"],
                      1e3 * m["module_engine_s"], m["module_s"] / m["cli_s"], m["same_tuples"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
