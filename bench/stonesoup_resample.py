"""The resampled Stone Soup peer (issue 29 item 5): every local track predicted onto one common
time grid with Stone Soup's own KalmanPredictor, so that its track-to-track associators, which
compare states only at timestamps two tracks share, see shared timestamps on asynchronous files.
Used by bench/stonesoup_t2t.py (methods stonesoup-one2one-resampled, stonesoup-counting-resampled).

What a careful user of Stone Soup writes to put tracks recorded by asynchronous sensors on common
timestamps (a predictor without updates):
    model     = CombinedLinearGaussianTransitionModel([ConstantVelocity(q)] * p)   (p = 2 or 3 axes)
    predictor = KalmanPredictor(model)
    for each grid time g within a track's span:
        prior = the track's latest state at or before g
        state = predictor.predict(prior, timestamp=g)    # x <- F x, P <- F P F' + Q(g - t_prior)
Per axis (Stone Soup's ConstantVelocity, continuous white-noise acceleration of spectral density q;
Bar-Shalom, Li, Kirubarajan 2001, §6.2.2, Eq. 6.2.2-12):
    F = [[1, dt], [0, 1]],   Q = q [[dt³/3, dt²/2], [dt²/2, dt]].

Choices (and why)
    grid      t_k = k · step, k integer, one grid for every track of the file. step defaults to the
              largest sensor period (per sensor, the median gap between consecutive reports of
              one track; the largest over sensors, rounded to 1 ms): every grid time then sees a
              fresh report of every sensor within one of its periods, and no track contributes
              several near-copies of one report. On the recorded family: 5 s (4 s on
              recorded_sync).
    span      a track gets the grid times g with t_first <= g <= t_last only: no extrapolation
              past its last report (the local tracker dropped it for a reason) or before its first.
    horizon   and only where its latest report is at most one grid step before g (dt <= step):
              inside a track the reports are one period apart, so dt stays below the period;
              a longer silence (a recycled track number's pause, a long coast) leaves those grid
              times empty rather than bridging it with a long CV prediction.
    q         36 m²/s³ by default (--q): the family's local trackers are CV filters with a
              discrete white-noise acceleration of σ_w = 3 m/s² per scan (the scenarios'
              tracker.process_noise); the continuous model gives the same velocity variance over
              a T = 4 s scan (the family's median period) at q = σ_w² T = 9 · 4 = 36. Predictions
              span at most 5 s here, so Q adds at most q · 5³/3 = 1500 m² (σ 39 m) per position
              axis, small beside the tracks' position variances (medians 9·10³-10⁵ m² per axis
              on the family). q = 4 or 400, or a 2 s grid, changes the correct rates by a few
              points, not the picture (docs/status.md).
Cost: one KalmanPredictor.predict call per (track, grid time).
"""
import math
from datetime import timedelta

import numpy as np

DEFAULT_Q = 36.0  # m²/s³, see the module docstring


def grid_step(d):
    """The largest sensor period in the data: per sensor column, the median gap between
    consecutive report times of one track; the maximum over sensors, rounded to 1 ms."""
    col = {s: i for i, s in enumerate(d["sensors"])}
    gaps = {}
    order = np.lexsort((d["t"], d["track"], d["sensor"]))
    s, k, t = d["sensor"][order], d["track"][order], d["t"][order]
    same = (s[1:] == s[:-1]) & (k[1:] == k[:-1])
    dt = np.diff(t)
    for sensor in np.unique(s):
        if int(sensor) not in col:
            continue
        g = dt[same & (s[1:] == sensor) & (dt > 0)]
        if len(g):
            gaps[int(sensor)] = float(np.median(g))
    if not gaps:
        raise ValueError("/tracks: no track with two reports at different times; "
                         "cannot derive a grid step (give --grid-step)")
    return round(max(gaps.values()), 3)


def make_predictor(ss, axes, q):
    """Stone Soup's KalmanPredictor with a CV model of spectral density q on each of `axes` axes
    (state order x, vx, y, vy[, z, vz], as bench/stonesoup_t2t.py builds the tracks)."""
    model = ss["CombinedLGTM"]([ss["CV"](q) for _ in range(axes)])
    return ss["KalmanPredictor"](model)


def grid_times(t_first, t_last, step):
    """The grid times k · step within [t_first, t_last] (k integer), as floats."""
    k0, k1 = math.ceil(t_first / step), math.floor(t_last / step)
    return [k * step for k in range(k0, k1 + 1) if t_first <= k * step <= t_last]


def resample_tracks(tracks, ss, predictor, step, epoch, horizon=None):
    """{key: Track} -> ({key: Track of predicted states on the grid}, {key: their timestamps},
    number of predict calls). horizon: the longest prediction allowed (default: step)."""
    horizon = step if horizon is None else horizon
    out, times, calls = {}, {}, 0
    for key, track in tracks.items():
        states = list(track.states)  # sorted by time (build_tracks)
        t = np.array([(st.timestamp - epoch).total_seconds() for st in states])
        resampled = []
        for g in grid_times(t[0], t[-1], step) if len(t) else []:
            when = epoch + timedelta(seconds=g)  # rounded to 1 µs, as the reports' times
            i = int(np.searchsorted(t, (when - epoch).total_seconds(), side="right")) - 1
            if i < 0 or (when - states[i].timestamp).total_seconds() > horizon:
                continue  # i: the latest report at or before g; none, or older than the horizon
            p = predictor.predict(states[i], timestamp=when)
            calls += 1
            resampled.append(p)
        out[key] = ss["Track"](resampled)
        times[key] = [st.timestamp for st in resampled]
    return out, times, calls
