#!/usr/bin/python3
"""Peer comparison: Stone Soup's track-to-track associators on a trackassoc schema-v1 track file.

What it does
    Reads /sensors and /tracks of a schema-v1 HDF5 file (docs/schema.md,
    docs/design.md §3), builds one Stone Soup Track of GaussianStates per (sensor, local track), and runs
      one2one   OneToOneTrackAssociator(measure=MeanMeasure(StateSequenceMeasure(
                    SquaredMahalanobis())), association_threshold=T, maximise_measure=False):
                    mean squared Mahalanobis distance over the shared timestamps, then
                    scipy's linear_sum_assignment; T defaults to the chi-square(D) 0.99 quantile;
      counting  TrackToTrackCounting (Sagild, Hem, Brekke, FUSION 2021): position-only
                    distance, 3 consecutive hits confirm, 2 consecutive misses end.
    and, unless --no-resampled, the same two on the tracks predicted onto one common time grid
    with Stone Soup's KalmanPredictor (CombinedLinearGaussianTransitionModel of ConstantVelocity,
    q = --q; grid step --grid-step, default the largest sensor period; only within each track's
    span, from its latest report at most one step before): stonesoup-one2one-resampled and
    stonesoup-counting-resampled, what a user writes so that asynchronous tracks share timestamps
    (bench/stonesoup_resample.py states the choices and why). Their time includes the predictions.
    Both are two-set associators; the S-sensor tuples are "pairwise chained", as a user of the
    peer would write it: union-find over (sensor, track) nodes with the links of the consecutive
    sensor pairs 0-1, 1-2, ..., then of the pairs (a, b), b > a+1 (by growing gap), restricted to
    tracks of a (of b) whose tuple has no track of b (of a) yet, so a target the middle sensor
    missed can still be linked. A link that would put two tracks of one sensor into a tuple is
    skipped. Every local track ends up in exactly one tuple (singletons included).
    The tuples are scored with the project's rule (engine/pipeline/metrics.hpp): a target tracked by >= 2
    sensors is correct when one tuple holds exactly its tracks, false when one of its tracks
    shares a tuple with another target's or a false (truth -1) track, missed otherwise.
    "false tuples" counts tuples of >= 2 tracks not all of one target.

How to run (from the repo root, with Debian's Python and the apt packages of
../shared/peers/stonesoup-src/README.md plus python3-h5py):
    /usr/bin/python3 bench/stonesoup_t2t.py FILE.h5 [--threshold T] [--cov first|sum]
        [--count-measure euclidean|mahalanobis] [--count-threshold M] [--no-resampled]
        [--grid-step S] [--q Q] [--json OUT.json] [--write-into OUT.h5]
    Stone Soup is found through $STONESOUP_SRC (default <repo>/../shared/peers/stonesoup-src and
    its stub/ folder). With --write-into, OUT.h5 is a copy of FILE.h5 plus
    /associations/stonesoup-one2one, /associations/stonesoup-counting (and the two
    /associations/stonesoup-*-resampled), written atomically
    (OUT.h5.tmp, then rename), so `trackassoc evaluate --input OUT.h5` scores them too.
    Exit status: 0 ok, 2 bad input, 3 Stone Soup (or a dependency) cannot be imported.

Caveats
    * Both associators compare states only at timestamps the two tracks share (exact datetime
      equality; t is converted to datetime = 2000-01-01 + t s, i.e. rounded to 1 µs). With
      asynchronous sensors (different periods or offsets) most pairs share none: MeanMeasure
      then returns None, OneToOne treats the pair as "at the threshold" (never associated) and
      Counting skips it, so both degrade to few or zero associations. The script counts, per
      associator, the candidate pairs without any shared timestamp (and those whose time spans
      overlap yet share none) and flags sensor pairs where it produced no association. The two
      runs without "-resampled" do no prediction / interpolation to common times: that is the
      peer as shipped; the resampled runs are the fair version a user would write.
    * SquaredMahalanobis uses the FIRST track's covariance only (not P1 + P2), so it is
      asymmetric and, for radars seeing a target from different angles (one narrow in range,
      the other wide in cross-range), far above chi-square(D): on seed000, sensor 0 vs 1, the
      true pairs score 16..125 against the 13.3 gate and none is linked (10 % correct).
      --cov sum swaps in d'(P1+P2)^-1 d (100 % on seed000); --threshold 150 also does there.
      The default stays the measure as shipped and documented.
    * Counting is not one-to-one; per sensor pair we keep, greedily, the partner with the longest
      total associated duration (sum of its TimeRanges) so the chained output is one-to-one.
      Its default gate is data-derived (see count_threshold below), since a fixed metre value
      cannot fit every scenario.
    * States are reordered to Stone Soup's (x, vx, y, vy[, z, vz]); distances are unchanged.
    * Stone Soup's state lookups are linear scans (Track[datetime]), so the cost is
      O(pairs · n²) in states per track: fine for the seed scenarios, slow for hour-long tracks.
"""
import argparse
import json
import os
import shutil
import sys
import time
import warnings
from collections import Counter, defaultdict
from datetime import datetime, timedelta

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stonesoup_resample as resample  # noqa: E402  (bench/, beside this script)

EPOCH = datetime(2000, 1, 1)
# schema-v1 layout -> permutation into Stone Soup's ordering, and the position rows after it.
LAYOUTS = {"x,y,vx,vy": ([0, 2, 1, 3], [0, 2]),
           "x,y,z,vx,vy,vz": ([0, 3, 1, 4, 2, 5], [0, 2, 4])}
# module -> how to get it (Debian packages; Stone Soup itself and utm come from the source tree).
APT = {"stonesoup": "no package: point STONESOUP_SRC at the source tree",
       "utm": "no package: needs the stub/ folder", "ruamel": "python3-ruamel.yaml",
       "ordered_set": "python3-ordered-set"}


def import_stonesoup():
    """Put Stone Soup on sys.path and import what we use; exit 3 naming a missing module."""
    src = os.environ.get("STONESOUP_SRC",
                         os.path.join(REPO, "..", "shared", "peers", "stonesoup-src"))
    sys.path[:0] = [os.path.abspath(src), os.path.abspath(os.path.join(src, "stub"))]
    try:
        __import__("h5py")  # checked here so a missing h5py gives the same one-line message
        from scipy.stats import chi2
        from stonesoup.dataassociator.tracktotrack import (OneToOneTrackAssociator,
                                                           TrackToTrackCounting)
        from stonesoup.measures import Euclidean, Mahalanobis, SquaredMahalanobis
        from stonesoup.measures.multi import MeanMeasure, StateSequenceMeasure
        from stonesoup.models.transition.linear import (CombinedLinearGaussianTransitionModel,
                                                        ConstantVelocity)
        from stonesoup.predictor.kalman import KalmanPredictor
        from stonesoup.types.array import CovarianceMatrix, StateVector
        from stonesoup.types.state import GaussianState
        from stonesoup.types.track import Track
    except ImportError as e:
        mod = (e.name or str(e)).split(".")[0]
        hint = APT.get(mod, "python3-" + mod)
        hint = hint if hint.startswith("no package") else "apt-get install " + hint
        print(f"stonesoup_t2t: cannot import module '{e.name}' ({hint}; STONESOUP_SRC={src})",
              file=sys.stderr)
        sys.exit(3)
    return dict(OneToOne=OneToOneTrackAssociator, Counting=TrackToTrackCounting,
                Euclidean=Euclidean, Mahalanobis=Mahalanobis, SqMaha=SquaredMahalanobis,
                Mean=MeanMeasure, Seq=StateSequenceMeasure, Cov=CovarianceMatrix,
                SV=StateVector, GS=GaussianState, Track=Track, chi2=chi2,
                CombinedLGTM=CombinedLinearGaussianTransitionModel, CV=ConstantVelocity,
                KalmanPredictor=KalmanPredictor)


def load(path):
    """Read a schema-v1 file into plain numpy arrays (sensor ids in /sensors order)."""
    import h5py
    with h5py.File(path, "r") as f:
        tr = f["tracks"]
        layout = tr.attrs.get("state_layout")
        layout = layout.decode() if isinstance(layout, bytes) else layout
        state = tr["state"][()].astype(np.float64)
        if layout is None:  # optional in inputs from elsewhere: D decides
            layout = "x,y,vx,vy" if state.shape[1] == 4 else "x,y,z,vx,vy,vz"
        if layout not in LAYOUTS:
            raise ValueError(f"/tracks state_layout '{layout}' not supported")
        n = state.shape[0]
        return dict(sensors=[int(s) for s in f["sensors/id"][()]], layout=layout,
                    sensor=tr["sensor"][()].astype(np.int64),
                    track=tr["track"][()].astype(np.int64),
                    t=tr["t"][()].astype(np.float64), state=state,
                    cov=tr["cov"][()].astype(np.float64),
                    truth=(tr["truth"][()].astype(np.int64) if "truth" in tr
                           else np.full(n, -1, np.int64)))


def track_truths(d):
    """(sensor column, track) -> most frequent non-negative truth of its rows, -1 if none.

    Ties go to the smaller id, as std::map iteration order does in engine/pipeline/metrics.cpp."""
    col = {s: i for i, s in enumerate(d["sensors"])}
    votes = defaultdict(Counter)
    for s, k, g in zip(d["sensor"], d["track"], d["truth"]):
        if int(s) in col:
            votes[(col[int(s)], int(k))][int(g)] += 1
    out = {}
    for key, c in votes.items():
        good = sorted((-n, g) for g, n in c.items() if g >= 0)
        out[key] = good[0][1] if good else -1
    return out


def build_tracks(d, ss):
    """One Stone Soup Track per (sensor column, local track): {key: Track}, {key: set of times}."""
    perm, _ = LAYOUTS[d["layout"]]
    dim = len(perm)
    iu = np.triu_indices(dim)  # packed upper triangle, row-major
    col = {s: i for i, s in enumerate(d["sensors"])}
    rows = defaultdict(list)
    for r, (s, k) in enumerate(zip(d["sensor"], d["track"])):
        if int(s) in col:  # rows of a sensor missing from /sensors are ignored, as by evaluate
            rows[(col[int(s)], int(k))].append(r)
    tracks, times = {}, {}
    for key in sorted(rows):
        states = []
        for r in sorted(rows[key], key=lambda r: d["t"][r]):
            p = np.zeros((dim, dim))
            p[iu] = d["cov"][r]
            p = p + np.triu(p, 1).T
            when = EPOCH + timedelta(seconds=float(d["t"][r]))
            states.append(ss["GS"](ss["SV"](d["state"][r][perm]),
                                   ss["Cov"](p[np.ix_(perm, perm)]), timestamp=when))
        tracks[key] = ss["Track"](states)
        times[key] = [st.timestamp for st in states]
    return tracks, times


class Chain:
    """Union-find over (sensor column, track) keys; a root knows the sensors of its tuple."""

    def __init__(self, keys):
        self.parent = {k: k for k in keys}
        self.sensors = {k: {k[0]} for k in keys}

    def find(self, k):
        while self.parent[k] != k:
            self.parent[k] = self.parent[self.parent[k]]
            k = self.parent[k]
        return k

    def link(self, a, b):
        """Merge the tuples of a and b unless that puts two tracks of one sensor together."""
        ra, rb = self.find(a), self.find(b)
        if ra == rb or self.sensors[ra] & self.sensors[rb]:
            return False
        self.parent[rb] = ra
        self.sensors[ra] |= self.sensors.pop(rb)
        return True

    def tuples(self, num_sensors):
        groups = defaultdict(list)
        for k in self.parent:
            groups[self.find(k)].append(k)
        out = np.full((len(groups), num_sensors), -1, np.int32)
        for q, members in enumerate(sorted(sorted(m) for m in groups.values())):
            for s, k in members:
                out[q, s] = k
        return out


def pair_schedule(num_sensors):
    """Consecutive pairs first, then (a, b) by growing gap b - a."""
    return [(a, a + g) for g in range(1, num_sensors) for a in range(num_sensors - g)]


def run_chained(tracks, times, num_sensors, associate):
    """Pairwise-chained tuples. `associate(A, B)` takes two lists of keys and returns
    one-to-one (key_a, key_b) links. Returns tuples, association time, per-pair diagnostics."""
    chain = Chain(tracks)
    assoc_time, diag = 0.0, []
    for a, b in pair_schedule(num_sensors):
        A = [k for k in tracks if k[0] == a and b not in chain.sensors[chain.find(k)]]
        B = [k for k in tracks if k[0] == b and a not in chain.sensors[chain.find(k)]]
        no_common = overlap_no_common = 0
        for ka in A:
            ta = set(times[ka])
            for kb in B:
                if ta.isdisjoint(times[kb]):
                    no_common += 1
                    overlap_no_common += (times[ka][0] <= times[kb][-1]
                                          and times[kb][0] <= times[ka][-1])
        t0 = time.perf_counter()
        links = associate(A, B) if A and B else []
        assoc_time += time.perf_counter() - t0
        made = sum(chain.link(ka, kb) for ka, kb in links)
        diag.append(dict(pair=[a, b], candidates=len(A) * len(B), no_common_time=no_common,
                         overlap_no_common_time=overlap_no_common, links=len(links), merged=made))
    return chain.tuples(num_sensors), assoc_time, diag


def score(tuples, truth_of):
    """The project's rule (engine/pipeline/metrics.cpp) plus the count of false multi-track tuples."""
    members = defaultdict(set)  # target -> its (column, track) keys
    for key, g in truth_of.items():
        if g >= 0:
            members[g].add(key)
    tuple_of, false_tuples, linked_tuples = {}, 0, 0
    for q, row in enumerate(tuples):
        keys = [(s, int(k)) for s, k in enumerate(row) if k >= 0]
        for key in keys:
            tuple_of[key] = q
        ids = {truth_of.get(key, -1) for key in keys}
        linked_tuples += len(keys) >= 2
        false_tuples += int(len(keys) >= 2 and (len(ids) > 1 or -1 in ids))
    n = dict(targets=0, correct=0, false=0, missed=0)
    for g, keys in members.items():
        if len({s for s, _ in keys}) < 2:
            continue
        n["targets"] += 1
        qs = {tuple_of[k] for k in keys if k in tuple_of}
        mixed = any(truth_of.get((s, int(k)), -1) != g
                    for q in qs for s, k in enumerate(tuples[q]) if k >= 0)
        complete = len(qs) == 1 and int((tuples[next(iter(qs))] >= 0).sum()) == len(keys)
        n["false" if mixed else "correct" if complete else "missed"] += 1
    if not any(g >= 0 for g in truth_of.values()):
        false_tuples = None  # no ground truth: as `trackassoc evaluate`, nothing to score
    rate = (lambda x: x / n["targets"]) if n["targets"] else (lambda x: float("nan"))
    return dict(correct_rate=rate(n["correct"]), false_rate=rate(n["false"]),
                missed_rate=rate(n["missed"]), false_tuples=false_tuples,
                linked_tuples=int(linked_tuples), **n)


def make_one2one(ss, tracks, threshold, cov):
    """cov="first": SquaredMahalanobis as shipped (first track's covariance only);
    cov="sum": the textbook track-to-track statistic d' (P1 + P2)^-1 d, a 5-line Measure."""
    class SquaredMahalanobisSum(ss["SqMaha"]):
        def __call__(self, s1, s2):
            delta = np.asarray(s1.state_vector - s2.state_vector, np.float64)[:, 0]
            return float(delta @ np.linalg.solve(np.asarray(s1.covar + s2.covar), delta))
    state_measure = ss["SqMaha"]() if cov == "first" else SquaredMahalanobisSum()
    assoc = ss["OneToOne"](measure=ss["Mean"](ss["Seq"](state_measure)),
                           association_threshold=threshold, maximise_measure=False)
    key_of = {id(t): k for k, t in tracks.items()}

    def associate(A, B):
        result = assoc.associate_tracks({tracks[k] for k in A}, {tracks[k] for k in B})
        links = []
        for a in result.associations:
            ka, kb = sorted(key_of[id(t)] for t in a.objects)  # the lower column is sensor a
            links.append((ka, kb))
        return sorted(links)
    return associate


def make_counting(ss, tracks, threshold, measure_name, pos):
    measure = (ss["Euclidean"](mapping=pos) if measure_name == "euclidean"
               else ss["Mahalanobis"](mapping=pos))
    assoc = ss["Counting"](association_threshold=threshold, consec_pairs_confirm=3,
                           consec_misses_end=2, measure=measure, pos_map=pos,
                           use_positional_only=True, one_to_one=False)
    key_of = {id(t): k for k, t in tracks.items()}

    def associate(A, B):
        result = assoc.associate_tracks({tracks[k] for k in A}, {tracks[k] for k in B})
        duration = Counter()  # (ka, kb) -> total associated seconds over its TimeRanges
        for a in result.associations:
            ka, kb = (key_of[id(t)] for t in a.objects)  # OrderedSet: (set 1, set 2)
            duration[(ka, kb)] += a.time_range.duration.total_seconds()
        used, links = set(), []
        for (ka, kb), _ in sorted(duration.items(), key=lambda kv: (-kv[1], kv[0])):
            if ka not in used and kb not in used:  # longest partner wins: one-to-one
                used |= {ka, kb}
                links.append((ka, kb))
        return links
    return associate


def count_threshold(d, pos_rows, measure_name):
    """Default Counting gate. Mahalanobis: sqrt(2·chi2(p, 0.99)) (first track's covariance
    only, so ~2x the consistent spread). Euclidean: the 0.99 radius of the position difference
    of two independent estimates with the file's median position variance per axis, i.e.
    sqrt(chi2(p, 0.99) · 2 · median(tr P_pos) / p)."""
    from scipy.stats import chi2
    p = len(pos_rows)
    if measure_name == "mahalanobis":
        return float(np.sqrt(2.0 * chi2.ppf(0.99, p)))
    dim = d["state"].shape[1]
    iu = list(zip(*np.triu_indices(dim)))
    diag_cols = [iu.index((i, i)) for i in range(p)]  # file order: position first
    tr_pos = d["cov"][:, diag_cols].sum(axis=1)
    if not len(tr_pos):
        return 1.0
    return float(np.sqrt(chi2.ppf(0.99, p) * 2.0 * np.median(tr_pos) / p))


def write_into(src, out, results, num_sensors):
    """Copy src to out.tmp, add one /associations/<name> per result, rename atomically."""
    import h5py
    tmp = out + ".tmp"
    shutil.copyfile(src, tmp)
    try:
        with h5py.File(tmp, "a") as f:
            root = f["associations"] if "associations" in f else \
                f.create_group("associations", track_order=True)
            for r in results:
                if r["name"] in root:
                    del root[r["name"]]
                g = root.create_group(r["name"])
                tuples = np.asarray(r["tuples"], np.int32).reshape(-1, num_sensors)
                g.create_dataset("tuples", data=tuples)
                g.create_dataset("cost", data=np.zeros(len(r["tuples"]), np.float64))
                for k, v in (("solver", r["solver"]), ("options", json.dumps(r["options"])),
                             ("termination", "peer")):
                    g.attrs[k] = v  # h5py str: variable-length UTF-8, like trackassoc's
                for k in ("objective", "lower_bound", "gap"):
                    g.attrs[k] = np.float64(np.nan)
                g.attrs["runtime_s"] = np.float64(r["assoc_time_s"])
                g.attrs["seed"] = np.uint64(0)
        os.replace(tmp, out)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", nargs="?", help="schema-v1 HDF5 track file")
    ap.add_argument("--check", action="store_true",
                    help="only check that Stone Soup and its dependencies import (exit 0 or 3)")
    ap.add_argument("--threshold", type=float, default=None,
                    help="OneToOne gate on the mean squared Mahalanobis distance "
                         "(default: chi-square(D) 0.99 quantile)")
    ap.add_argument("--cov", choices=["first", "sum"], default="first",
                    help="OneToOne's covariance: 'first' = SquaredMahalanobis as shipped (the "
                         "first track's), 'sum' = P1 + P2 (see caveats)")
    ap.add_argument("--count-measure", choices=["euclidean", "mahalanobis"], default="euclidean",
                    help="Counting's per-state position distance (default euclidean, as its docs)")
    ap.add_argument("--count-threshold", type=float, default=None,
                    help="Counting gate (metres for euclidean); default data-derived, see caveats")
    ap.add_argument("--no-resampled", action="store_true",
                    help="skip the resampled runs (bench/stonesoup_resample.py)")
    ap.add_argument("--grid-step", type=float, default=None,
                    help="resampled runs: the common grid's step [s] (default: the largest "
                         "sensor period in the file)")
    ap.add_argument("--q", type=float, default=resample.DEFAULT_Q,
                    help="resampled runs: ConstantVelocity's noise_diff_coeff q [m^2/s^3] "
                         "(default %(default)g, see bench/stonesoup_resample.py)")
    ap.add_argument("--json", metavar="FILE", help="write the results as JSON")
    ap.add_argument("--write-into", metavar="OUT.h5",
                    help="copy the input to OUT.h5 with the associations added")
    args = ap.parse_args(argv)

    ss = import_stonesoup()
    if args.check:
        return 0
    if args.input is None:
        ap.error("an input file is required (or --check)")
    if args.grid_step is not None and not args.grid_step > 0:
        ap.error(f"--grid-step: expected a step > 0 s, found {args.grid_step}")
    if not args.q >= 0:
        ap.error(f"--q: expected q >= 0, found {args.q}")
    try:
        d = load(args.input)
        step = None if args.no_resampled else (args.grid_step or resample.grid_step(d))
    except (OSError, KeyError, ValueError) as e:
        print(f"stonesoup_t2t: {args.input}: {e}", file=sys.stderr)
        return 2
    S, D = len(d["sensors"]), d["state"].shape[1]
    _, pos = LAYOUTS[d["layout"]]
    truth_of = track_truths(d)
    t0 = time.perf_counter()
    tracks, times = build_tracks(d, ss)
    build_time = time.perf_counter() - t0

    thr = args.threshold if args.threshold is not None else float(ss["chi2"].ppf(0.99, D))
    cthr = (args.count_threshold if args.count_threshold is not None
            else count_threshold(d, pos, args.count_measure))
    one2one_options = dict(measure="MeanMeasure(StateSequenceMeasure(SquaredMahalanobis()))"
                           + (" with P1+P2" if args.cov == "sum" else ""),
                           association_threshold=thr, maximise_measure=False)
    counting_options = dict(measure=f"{args.count_measure}(position)", association_threshold=cthr,
                            consec_pairs_confirm=3, consec_misses_end=2, use_positional_only=True,
                            one_to_one="longest total duration per sensor pair")
    # (name, solver, tracks, times, associate, options, seconds spent before associating)
    runs = [("stonesoup-one2one", "stonesoup OneToOneTrackAssociator", tracks, times,
             make_one2one(ss, tracks, thr, args.cov), one2one_options, 0.0),
            ("stonesoup-counting", "stonesoup TrackToTrackCounting", tracks, times,
             make_counting(ss, tracks, cthr, args.count_measure, pos), counting_options, 0.0)]
    if step is not None:  # the same associators on the tracks predicted onto a common grid
        t0 = time.perf_counter()
        predictor = resample.make_predictor(ss, len(pos), args.q)
        rtracks, rtimes, calls = resample.resample_tracks(tracks, ss, predictor, step, EPOCH)
        predict_time = time.perf_counter() - t0
        grid = dict(resampled=f"KalmanPredictor(CombinedLinearGaussianTransitionModel("
                              f"[ConstantVelocity({args.q:g})] * {len(pos)})) onto t = k * "
                              f"{step:g} s within each track's span, from its latest report at "
                              f"most {step:g} s before", grid_step=step, q=args.q,
                    predict_calls=calls, predict_time_s=predict_time)
        runs += [("stonesoup-one2one-resampled", "stonesoup OneToOneTrackAssociator", rtracks,
                  rtimes, make_one2one(ss, rtracks, thr, args.cov), {**one2one_options, **grid},
                  predict_time),
                 ("stonesoup-counting-resampled", "stonesoup TrackToTrackCounting", rtracks,
                  rtimes, make_counting(ss, rtracks, cthr, args.count_measure, pos),
                  {**counting_options, **grid}, predict_time)]
    results = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # StateSequenceMeasure warns on every no-common-time pair
        for name, solver, run_tracks, run_times, associate, options, before in runs:
            tuples, assoc_time, diag = run_chained(run_tracks, run_times, S, associate)
            assoc_time += before  # resampled: the predictions are part of the method
            m = score(tuples, truth_of)
            options.update(chaining="pairwise chained: consecutive pairs, then growing gaps; "
                                    "no same-sensor merge", timestamp_epoch=EPOCH.isoformat())
            results.append(dict(name=name, solver=solver, options=options, **m,
                                assoc_time_s=assoc_time, build_time_s=build_time,
                                candidate_pairs=sum(x["candidates"] for x in diag),
                                pairs_without_common_time=sum(x["no_common_time"] for x in diag),
                                overlapping_pairs_without_common_time=sum(
                                    x["overlap_no_common_time"] for x in diag),
                                sensor_pairs=diag, tuples=tuples.tolist()))

    print(f"{args.input}: {S} sensors, {len(tracks)} local tracks, layout {d['layout']}, "
          f"one2one threshold {thr:.3g} (cov {args.cov}), "
          f"counting threshold {cthr:.3g} ({args.count_measure})"
          + ("" if step is None else f", resampled onto a {step:g} s grid (q {args.q:g})"))
    pct = lambda x: "   n/a" if x != x else f"{100 * x:5.1f}%"  # noqa: E731
    print(f"{'associator':28} {'targets':>7} {'correct':>7} {'false':>7} {'missed':>7} "
          f"{'false tuples':>12} {'assoc s':>8} {'build s':>8} {'no-common':>13}")
    for r in results:
        print(f"{r['name']:28} {r['targets']:7d} {pct(r['correct_rate']):>7} "
              f"{pct(r['false_rate']):>7} {pct(r['missed_rate']):>7} "
              f"{'n/a' if r['false_tuples'] is None else r['false_tuples']!s:>4} "
              f"of {r['linked_tuples']:<4d} "
              f"{r['assoc_time_s']:8.3f} {r['build_time_s']:8.3f} "
              f"{r['pairs_without_common_time']:6d}/{r['candidate_pairs']:<6d}")
        for x in r["sensor_pairs"]:
            if x["candidates"] and not x["links"]:
                hint = "one2one" in r["name"] and args.cov == "first"
                why = ("no candidate pair shares a timestamp"
                       if x["no_common_time"] == x["candidates"] else
                       "no pair passed the gate" + (" (try --cov sum)" if hint else ""))
                print(f"  {r['name']}: sensors {x['pair'][0]}-{x['pair'][1]}: zero associations "
                      f"({x['candidates']} candidates; {why})")
    if d["truth"].max(initial=-1) < 0:
        print("no /tracks/truth target ids: rates are n/a")
    if args.json:
        nan_to_null = lambda v: None if isinstance(v, float) and v != v else v  # noqa: E731
        with open(args.json, "w") as f:  # one object per associator; rates null without truth
            json.dump({r["name"]: {k: nan_to_null(v) for k, v in r.items() if k != "tuples"}
                       for r in results}, f, indent=1, default=float)
    if args.write_into:
        write_into(args.input, args.write_into, results, S)
        print(f"wrote {args.write_into}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
