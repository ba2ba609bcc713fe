"""trackassoc: multi-sensor track-to-track association, from Python (docs/design.md §9).

The C++ engine of the `trackassoc` command line on numpy arrays, with the same validation and the
same results, bit for bit:

    import trackassoc
    f = trackassoc.read("sim.h5")            # or a dict / structured array of /tracks columns
    a = trackassoc.associate(f)               # the default pipeline; **options as the CLI flags
    a.tuples, a.cost, a.unassociated, a.summary
    trackassoc.evaluate(a)                    # correct / false / missed rates against /tracks/truth
    fused = trackassoc.fuse(a, rule="ci")
    trackassoc.write("out.h5", f, associations=[a], fused=[fused])
    a.to_pandas()                             # one row per (tuple, sensor) member (pandas optional)

Stone Soup users: trackassoc.stonesoup.TrackToTrackAssociator (imports Stone Soup only when used).
Every function releases the GIL while the engine runs. Bad input raises ValueError
(trackassoc.InputError) with the command line's one-line message.
"""
from ._core import (Association, Fused, InputError, TrackFile, __version__, associate, evaluate, fuse,
                    option_help, read, tracks, write)

__all__ = ["Association", "Fused", "InputError", "TrackFile", "associate", "evaluate", "fuse", "option_help",
           "read", "tracks", "write", "__version__"]


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pandas is optional: everything else works without it
        raise ImportError("to_pandas() needs pandas (Debian: python3-pandas)") from e
    return pandas


def _association_to_pandas(self):
    """One row per member of a tuple: target, tuple, sensor, track, cost (the columns of
    `trackassoc export csv --what associations`, without source_track)."""
    import numpy as np
    pd = _pandas()
    tuples = self.tuples
    ids = self.sensor_ids
    k, col = np.nonzero(tuples >= 0)
    return pd.DataFrame({
        "target": self.target[k],
        "tuple": k.astype(np.int32),
        "sensor": ids[col],
        "track": tuples[k, col],
        "cost": self.cost[k],
    })


def _fused_to_pandas(self):
    """One row per fused time: tuple, t, the state columns, the packed covariance cov_R_C, sources,
    truth (as /fused/<name>)."""
    pd = _pandas()
    a = self.arrays
    d = a["state"].shape[1]
    names = ["x", "y", "vx", "vy"] if d == 4 else ["x", "y", "z", "vx", "vy", "vz"]
    cols = {"tuple": a["tuple"], "t": a["t"]}
    for i, n in enumerate(names):
        cols[n] = a["state"][:, i]
    k = 0
    for r in range(d):
        for c in range(r, d):
            cols["cov_%d_%d" % (r, c)] = a["cov"][:, k]
            k += 1
    cols["sources"] = a["sources"]
    cols["truth"] = a["truth"]
    return pd.DataFrame(cols)


Association.to_pandas = _association_to_pandas
Fused.to_pandas = _fused_to_pandas
