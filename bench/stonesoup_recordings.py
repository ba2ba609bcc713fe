#!/usr/bin/python3
"""Independent recordings: multi-radar local track files made with Stone Soup's own models and
trackers, not trackassoc's simulator (docs/status.md, "Independent recordings").

Why
    The recorded family (engine/simulation/, `experiment recorded`) is trackassoc's own simulator:
    its truth model, its radars and its local trackers. A method tuned on it can pass every scenario
    and still fail on files written by someone else. These files share none of that code: the
    targets move by Stone Soup's transition models, each radar measures with Stone Soup's
    CartesianToBearingRange, and each radar's local tracks are Stone Soup's own multi-target
    tracker, a GNN over an extended Kalman filter that starts, coasts and drops tracks by its own
    rules (and so breaks and swaps tracks where it will). Only the recording errors are injected
    here, each as a real recording carries it.

What a file holds (schema v1, docs/schema.md; 2-D, state x, y, vx, vy; /truth at 1 s steps)
    truth      `targets` targets, born over the first 60 % of the run and living 40-100 % of it,
               in a box of side `box` m, speeds 150-250 m/s, headings uniform (or within ±10° of
               east with --airway); each leg 15-40 s of Stone Soup's ConstantVelocity (q = 0.5
               m²/s³ per axis) or, with probability 0.5, KnownTurnRate at ±1-3 °/s; 1 s steps.
    radars     3 (or --radars) at 60-110 km from the box centre, asynchronous scans (periods 3, 4,
               5 s, offsets 0.5, 1.7, 2.9 s), σ_range 60-120 m, σ_bearing 0.25-0.4°, p_D 0.9,
               1 clutter plot per scan in the box.
    trackers   per radar Stone Soup's MultiTargetTracker: KalmanPredictor with ConstantVelocity
               (q = 30, 100, 300 m²/s³ for radars 0, 1, 2: trackers tuned differently), the
               ExtendedKalmanUpdater of the radar's *nominal* measurement model (its surveyed
               site, no bias: the tracker does not know its errors), DistanceHypothesiser with the
               Mahalanobis measure (missed distance 4), GNNWith2DAssignment, a
               MultiMeasurementInitiator of 3 points, and UpdateTimeStepsDeleter(3). Every state
               of a track (updates and coasted predictions) is one row; its truth is the target of
               its latest update's detection (-1 for clutter).
    errors     --range-bias, --azimuth-bias (deg, the radar's true orientation, Stone Soup's
               rotation_offset), --site-error (m: the true site is off the written
               /sensors/position), --clock-offset (s: a radar time-stamps its tracks late by
               this), per radar as comma lists; --recycle S: radar 1 reuses a track number S
               seconds after its track ended (the lowest free number), as some trackers do.
Usage
    /usr/bin/python3 bench/stonesoup_recordings.py OUT.h5 [--seed N] [--targets 20] [--airway]
        [--range-bias 60,-120,190] [--azimuth-bias 0.3,-0.6,0.6] [--site-error 0,530,0]
        [--clock-offset 0,0,1.5] [--recycle 30] [--duration 300] [--box 40000]
    Stone Soup is found through $STONESOUP_SRC (default <repo>/../shared/peers/stonesoup-src and its
    stub/ folder). The file is written atomically (OUT.h5.tmp, then renamed); an existing OUT.h5
    is replaced only by a complete file. scripts/independent_recordings.sh makes the set that
    docs/status.md reports and scores it with `associate` and `evaluate`.
"""
import argparse
import datetime
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.environ.get("STONESOUP_SRC", os.path.join(HERE, "..", "..", "shared", "peers", "stonesoup-src"))
sys.path[:0] = [SRC, os.path.join(SRC, "stub")]

EPOCH = datetime.datetime(2000, 1, 1)
PERIODS = [3.0, 4.0, 5.0, 3.5, 4.5]
OFFSETS = [0.5, 1.7, 2.9, 1.1, 2.3]
SIGMA_RANGE = [80.0, 120.0, 60.0, 100.0, 90.0]
SIGMA_BEARING_DEG = [0.3, 0.4, 0.25, 0.35, 0.3]
TRACKER_Q = [30.0, 100.0, 300.0, 100.0, 30.0]
P_DETECT = 0.9


def per_radar(text, radars, name):
    values = [float(v) for v in text.split(",")] if text else [0.0] * radars
    if len(values) != radars:
        sys.exit(f"--{name}: expected {radars} comma-separated values, got {len(values)}")
    return values


def truth_paths(rng, args):
    """Targets as lists of (t, state [x, vx, y, vy]) at 1 s steps, Stone Soup's models."""
    from stonesoup.models.transition.linear import (CombinedLinearGaussianTransitionModel,
                                                    ConstantVelocity, KnownTurnRate)
    from stonesoup.types.state import State
    cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5), ConstantVelocity(0.5)])
    paths = []
    for _ in range(args.targets):
        birth = rng.uniform(0.0, 0.6 * args.duration)
        life = rng.uniform(0.4, 1.0) * args.duration
        death = min(args.duration, birth + life)
        speed = rng.uniform(150.0, 250.0)
        heading = math.radians(rng.uniform(-10.0, 10.0)) if args.airway else rng.uniform(0.0, 2 * math.pi)
        half = args.box / 2
        x = np.array([rng.uniform(-half, half), speed * math.cos(heading),
                      rng.uniform(-half, half), speed * math.sin(heading)])
        state = State(x.reshape(4, 1))
        t, path = birth, []
        while t <= death:
            leg = rng.uniform(15.0, 40.0)
            if rng.uniform() < 0.5:
                rate = math.radians(rng.uniform(1.0, 3.0)) * (1 if rng.uniform() < 0.5 else -1)
                model = KnownTurnRate(turn_noise_diff_coeffs=[0.5, 0.5], turn_rate=rate)
            else:
                model = cv
            end = min(death, t + leg)
            while t <= end:
                path.append((t, np.asarray(state.state_vector, dtype=float).ravel().copy()))
                state = State(model.function(state, noise=True, time_interval=datetime.timedelta(seconds=1)))
                t += 1.0
        paths.append(path)
    return paths


def state_at(path, t):
    """The truth state at time t (linear between the 1 s steps), or None outside its life."""
    if not path or t < path[0][0] or t > path[-1][0]:
        return None
    k = min(int(t - path[0][0]), len(path) - 2) if len(path) > 1 else 0
    if len(path) == 1:
        return path[0][1]
    (t0, x0), (t1, x1) = path[k], path[k + 1]
    w = (t - t0) / (t1 - t0)
    return (1 - w) * x0 + w * x1


def radar_tracks(rng, args, s, site_true, site_written, paths):
    """One radar's scans and its Stone Soup tracker: rows (t reported, state, cov, track id, truth)."""
    from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
    from stonesoup.deleter.time import UpdateTimeStepsDeleter
    from stonesoup.hypothesiser.distance import DistanceHypothesiser
    from stonesoup.initiator.simple import MultiMeasurementInitiator
    from stonesoup.measures import Mahalanobis
    from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.predictor.kalman import KalmanPredictor
    from stonesoup.tracker.simple import MultiTargetTracker
    from stonesoup.types.detection import Clutter, TrueDetection
    from stonesoup.types.state import GaussianState, State
    from stonesoup.types.update import Update
    from stonesoup.updater.kalman import ExtendedKalmanUpdater

    noise = np.diag([math.radians(SIGMA_BEARING_DEG[s]) ** 2, SIGMA_RANGE[s] ** 2])
    true_model = CartesianToBearingRange(
        ndim_state=4, mapping=(0, 2), noise_covar=noise,
        translation_offset=np.array([[site_true[0]], [site_true[1]]]),
        rotation_offset=np.array([[0.0], [0.0], [math.radians(args.azimuth_bias[s])]]))
    nominal = CartesianToBearingRange(
        ndim_state=4, mapping=(0, 2), noise_covar=noise,
        translation_offset=np.array([[site_written[0]], [site_written[1]]]))
    scans = []
    t = OFFSETS[s]
    half = args.box / 2
    while t <= args.duration:
        stamp = EPOCH + datetime.timedelta(seconds=t + args.clock_offset[s])
        detections = set()
        for target, path in enumerate(paths):
            x = state_at(path, t)
            if x is None or rng.uniform() >= P_DETECT:
                continue
            z = true_model.function(State(x.reshape(4, 1)), noise=True)
            z[1, 0] += args.range_bias[s]
            detections.add(TrueDetection(z, timestamp=stamp, measurement_model=nominal,
                                         groundtruth_path=target))
        x = np.array([[rng.uniform(-half, half)], [0.0], [rng.uniform(-half, half)], [0.0]])
        detections.add(Clutter(true_model.function(State(x), noise=True), timestamp=stamp,
                               measurement_model=nominal))
        scans.append((stamp, detections))
        t += PERIODS[s]

    q = TRACKER_Q[s]
    predictor = KalmanPredictor(CombinedLinearGaussianTransitionModel([ConstantVelocity(q), ConstantVelocity(q)]))
    updater = ExtendedKalmanUpdater(nominal)
    associator = GNNWith2DAssignment(DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=4))
    prior = GaussianState(np.zeros((4, 1)), np.diag([1e8, 300.0 ** 2, 1e8, 300.0 ** 2]))
    initiator = MultiMeasurementInitiator(
        prior_state=prior, measurement_model=nominal, deleter=UpdateTimeStepsDeleter(2),
        data_associator=GNNWith2DAssignment(DistanceHypothesiser(predictor, updater, Mahalanobis(),
                                                                 missed_distance=4)),
        updater=updater, min_points=3)
    tracker = MultiTargetTracker(initiator=initiator, deleter=UpdateTimeStepsDeleter(3), detector=scans,
                                 data_associator=associator, updater=updater)
    tracks = set()
    for _, current in tracker:
        tracks |= current
    rows = []
    # numbered by first report, then position (a Stone Soup track id is a random UUID)
    order = sorted(tracks, key=lambda tr: (tr.states[0].timestamp, float(tr.states[0].state_vector[0, 0]),
                                           float(tr.states[0].state_vector[2, 0])))
    for number, track in enumerate(order):
        truth = -1
        for st in track.states:
            if isinstance(st, Update):
                d = st.hypothesis.measurement
                truth = d.groundtruth_path if isinstance(d, TrueDetection) else -1
            x = np.asarray(st.state_vector, dtype=float).ravel()
            P = np.asarray(st.covar, dtype=float)
            perm = [0, 2, 1, 3]  # Stone Soup's x, vx, y, vy -> x, y, vx, vy
            rows.append(((st.timestamp - EPOCH).total_seconds(), x[perm], P[np.ix_(perm, perm)], number, truth))
    return rows


def recycle(rows, after):
    """Track numbers given anew in order of first report, reusing the lowest number whose track
    ended at least `after` seconds before."""
    spans = {}
    for t, _, _, n, _ in rows:
        lo, hi = spans.get(n, (t, t))
        spans[n] = (min(lo, t), max(hi, t))
    free_from, number_of = {}, {}
    for n in sorted(spans, key=lambda k: spans[k][0]):
        start, end = spans[n]
        reusable = [m for m, f in free_from.items() if f <= start]
        m = min(reusable) if reusable else len(free_from)
        number_of[n] = m
        free_from[m] = end + after
    return [(t, x, P, number_of[n], u) for t, x, P, n, u in rows]


def write(path, args, sites_written, per_sensor, paths):
    import h5py
    tmp = path + ".tmp"
    iu = np.triu_indices(4)
    with h5py.File(tmp, "w") as f:
        f.attrs["format"] = "trackassoc"
        f.attrs["schema_version"] = np.int32(1)
        f.attrs["created_by"] = "bench/stonesoup_recordings.py (Stone Soup models and trackers)"
        f.attrs["generator"] = json.dumps(vars(args))
        S = len(per_sensor)
        g = f.create_group("sensors")
        g["id"] = np.arange(S, dtype=np.int32)
        g["position"] = np.array([[p[0], p[1], 0.0] for p in sites_written])
        g["sigma_range"] = np.array(SIGMA_RANGE[:S])
        g["sigma_bearing"] = np.radians(SIGMA_BEARING_DEG[:S])
        g["sigma_elevation"] = np.zeros(S)
        g["period"] = np.array(PERIODS[:S])
        g["offset"] = np.array(OFFSETS[:S])
        g["p_detect"] = np.full(S, P_DETECT)
        g["clutter_rate"] = np.ones(S)
        g["reliability"] = np.ones(S)
        rows = [(s, r) for s, rs in enumerate(per_sensor) for r in rs]
        rows.sort(key=lambda sr: (sr[0], sr[1][3], sr[1][0]))
        g = f.create_group("truth")
        g.attrs["state_layout"] = "x,y,vx,vy"
        truth = [(j, t, x[[0, 2, 1, 3]]) for j, path in enumerate(paths) for t, x in path]
        g["target"] = np.array([j for j, _, _ in truth], dtype=np.int32)
        g["t"] = np.array([t for _, t, _ in truth])
        g["state"] = np.array([x for _, _, x in truth]).reshape(-1, 4)
        g = f.create_group("tracks")
        g.attrs["state_layout"] = "x,y,vx,vy"
        g["sensor"] = np.array([s for s, _ in rows], dtype=np.int32)
        g["track"] = np.array([r[3] for _, r in rows], dtype=np.int32)
        g["t"] = np.array([r[0] for _, r in rows])
        g["state"] = np.array([r[1] for _, r in rows]).reshape(-1, 4)
        g["cov"] = np.array([0.5 * (r[2] + r[2].T)[iu] for _, r in rows]).reshape(-1, 10)
        g["truth"] = np.array([r[4] for _, r in rows], dtype=np.int32)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("output")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--targets", type=int, default=20)
    ap.add_argument("--radars", type=int, default=3)
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--box", type=float, default=40000.0)
    ap.add_argument("--airway", action="store_true")
    ap.add_argument("--range-bias", default="")
    ap.add_argument("--azimuth-bias", default="")
    ap.add_argument("--site-error", default="", help="per radar, metres east of the written site")
    ap.add_argument("--clock-offset", default="")
    ap.add_argument("--recycle", type=float, default=0.0)
    args = ap.parse_args()
    if not 2 <= args.radars <= len(PERIODS):
        sys.exit(f"--radars: 2 to {len(PERIODS)}")
    for name in ("range_bias", "azimuth_bias", "site_error", "clock_offset"):
        setattr(args, name, per_radar(getattr(args, name), args.radars, name.replace("_", "-")))
    rng = np.random.default_rng(args.seed)
    np.random.seed(args.seed)  # Stone Soup's models draw their noise from numpy's global generator
    paths = truth_paths(rng, args)
    written, per_sensor = [], []
    for s in range(args.radars):
        angle = 2 * math.pi * s / args.radars + 0.3
        distance = 60000.0 + 25000.0 * s
        site = (distance * math.cos(angle), distance * math.sin(angle))
        written.append(site)
        true_site = (site[0] + args.site_error[s], site[1])
        rows = radar_tracks(rng, args, s, true_site, site, paths)
        if s == 1 and args.recycle > 0:
            rows = recycle(rows, args.recycle)
        per_sensor.append(rows)
    write(args.output, args, written, per_sensor, paths)


if __name__ == "__main__":
    main()
