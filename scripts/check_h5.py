#!/usr/bin/python3
"""Open a trackassoc HDF5 file with h5py (no C++ involved), list every dataset with its shape and
dtype, and assert the schema v1 layout (docs/design.md §3, io/track_file.hpp).

Usage: scripts/check_h5.py FILE.h5 [--quiet]
Exit status 0 when the file follows the schema, 1 (with the failed check) otherwise.
Needs Debian's python3-h5py (scripts/setup.sh installs it).
"""
import json
import sys

import h5py
import numpy as np


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def check_file(path, quiet=False):
    with h5py.File(path, "r") as f:
        if not quiet:
            def show(name, obj):
                if isinstance(obj, h5py.Dataset):
                    print(f"/{name}  shape={obj.shape}  dtype={obj.dtype}")
            f.visititems(show)

        check(text(f.attrs["format"]) == "trackassoc", "root attribute format != 'trackassoc'")
        check(int(f.attrs["schema_version"]) == 1, "root attribute schema_version != 1")
        if "scenario" in f.attrs and text(f.attrs["scenario"]):
            json.loads(text(f.attrs["scenario"]))  # the scenario is valid JSON

        sensors = f["sensors"]
        s = sensors["id"].shape[0]
        check(sensors["id"].dtype.kind == "i", "/sensors/id is not integer")
        check(len(set(sensors["id"][:].tolist())) == s, "/sensors/id not unique")
        for name, ds in sensors.items():
            expected = (s, 3) if name == "position" else (s,)
            check(ds.shape == expected, f"/sensors/{name} shape {ds.shape} != {expected}")

        tracks = f["tracks"]
        layout = text(tracks.attrs["state_layout"])
        check(layout in ("x,y,vx,vy", "x,y,z,vx,vy,vz"), f"unknown state_layout {layout!r}")
        d = len(layout.split(","))
        n = tracks["sensor"].shape[0]
        for name in ("sensor", "track", "truth"):
            check(tracks[name].dtype == np.int32, f"/tracks/{name} dtype {tracks[name].dtype} != int32")
            check(tracks[name].shape == (n,), f"/tracks/{name} shape != ({n},)")
        check(tracks["t"].shape == (n,), "/tracks/t shape")
        check(tracks["state"].shape == (n, d), f"/tracks/state shape {tracks['state'].shape} != {(n, d)}")
        p = d * (d + 1) // 2
        check(tracks["cov"].shape == (n, p), f"/tracks/cov shape {tracks['cov'].shape} != {(n, p)}")
        check(np.isin(tracks["sensor"][:], sensors["id"][:]).all(), "/tracks/sensor not in /sensors/id")
        # Packed upper triangle, row-major -> full symmetric matrices; all positive definite.
        if n:
            iu = np.triu_indices(d)
            full = np.zeros((n, d, d))
            full[:, iu[0], iu[1]] = tracks["cov"][:]
            full = full + np.transpose(full, (0, 2, 1)) - full * np.eye(d)
            check(np.isfinite(full).all(), "/tracks/cov has non-finite values")
            check((np.linalg.eigvalsh(full) > 0).all(), "/tracks/cov has a matrix that is not positive definite")

        if "truth" in f:
            m = f["truth/target"].shape[0]
            check(f["truth/t"].shape == (m,), "/truth/t shape")
            check(f["truth/state"].shape[0] == m and f["truth/state"].shape[1] in (4, 6), "/truth/state shape")
        if "measurements" in f:
            g = f["measurements"]
            m = g["sensor"].shape[0]
            for name in ("t", "range", "bearing", "target"):
                check(g[name].shape == (m,), f"/measurements/{name} shape")
            check(g["elevation"].shape in ((m,), (0,)), "/measurements/elevation shape")
        for name, g in f.get("associations", {}).items():
            check(g["tuples"].dtype == np.int32, f"/associations/{name}/tuples dtype")
            k = g["tuples"].shape[0]
            check(g["tuples"].shape == (k, s), f"/associations/{name}/tuples shape {g['tuples'].shape} != ({k}, {s})")
            check(g["cost"].shape == (k,), f"/associations/{name}/cost shape")
            for attr in ("solver", "options", "objective", "lower_bound", "gap", "runtime_s", "seed", "termination"):
                check(attr in g.attrs, f"/associations/{name} lacks attribute {attr}")
            json.loads(text(g.attrs["options"]))
            if "energy" in g:
                check(g["energy"].dtype == np.float32 and g["energy"].ndim == 2, f"/associations/{name}/energy")
            if "restarts" in g:  # per-restart table of multi-start solvers (Hopfield)
                r = g["restarts"]
                rows = r["restart"].shape
                for col in ("valid_raw", "sweeps", "mean_field_steps", "energy", "repaired_objective", "objective"):
                    check(col in r and r[col].shape == rows, f"/associations/{name}/restarts/{col} shape")
        for name, g in f.get("metrics", {}).items():
            for attr in ("correct_rate", "false_rate", "missed_rate"):
                check(attr in g.attrs, f"/metrics/{name} lacks attribute {attr}")
            for table, ds in g.items():
                check(ds.ndim == 1 and ds.dtype == np.float64, f"/metrics/{name}/{table} is not a 1-D float64 table")
    return True


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    try:
        check_file(sys.argv[1], quiet="--quiet" in sys.argv[2:])
    except (AssertionError, KeyError, ValueError) as e:
        print(f"{sys.argv[1]}: schema check failed: {e}", file=sys.stderr)
        return 1
    print(f"{sys.argv[1]}: follows trackassoc schema v1")
    return 0


if __name__ == "__main__":
    sys.exit(main())
