"""`trackassoc export csv --what tracks|associations|unassociated|fused|registration` (issue 32):
each table against the content it comes from (the module's reading of the same file, or h5py),
exact numbers, and --what associations round-tripped through pandas."""
import csv
import shutil

import h5py
import numpy as np
import pytest

import trackassoc
from conftest import run_cli


@pytest.fixture(scope="module")
def results(simulated, tmp_path_factory):
    """recorded_formation associated (default pipeline) and fused (naive), as the CLI writes it."""
    folder = tmp_path_factory.mktemp("export")
    out = folder / "a.h5"
    # --no-registration: the tests below write their own /registration (test_registration) or need
    # a file without one (test_refusals)
    run_cli("associate", "--input", simulated("recorded_formation"), "--output", out, "--no-registration")
    run_cli("fuse", "--input", out, "--rule", "naive")
    return out


def export(path, tmp_path, what=None, *extra):
    out = tmp_path / ("%s.csv" % (what or "default"))
    args = ["export", "csv", "--input", path, "--output", out, *extra]
    if what:
        args += ["--what", what]
    run_cli(*args)
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:], out


def test_tracks_is_the_default_and_unchanged(results, tmp_path):
    h0, rows0, out0 = export(results, tmp_path)
    h1, rows1, out1 = export(results, tmp_path, "tracks")
    assert out0.read_bytes() == out1.read_bytes()
    assert h0[:3] == ["sensor", "track", "t"] and h0[-1] == "truth"
    t = trackassoc.read(str(results)).tracks
    assert len(rows0) == len(t["t"])
    assert [float(r[2]) for r in rows0] == t["t"].tolist()  # shortest text reads back exactly


def test_associations(results, tmp_path):
    header, rows, _ = export(results, tmp_path, "associations")
    assert header == ["target", "tuple", "sensor", "track", "source_track", "cost"]
    (a,) = trackassoc.read(str(results)).associations.values()
    tuples, ids = a.tuples, a.sensor_ids
    expected = [(int(a.target[k]), k, int(ids[c]), int(tuples[k, c]), int(tuples[k, c]), float(a.cost[k]))
                for k in range(tuples.shape[0]) for c in range(tuples.shape[1]) if tuples[k, c] >= 0]
    got = [(int(r[0]), int(r[1]), int(r[2]), int(r[3]), int(r[4]), float(r[5])) for r in rows]
    assert got == expected  # no /tracks/source_track in a simulated file: source_track = track


def test_associations_source_track(results, tmp_path):
    """With /tracks/source_track, a track's value at its first report."""
    path = tmp_path / "with_source.h5"
    shutil.copyfile(results, path)
    with h5py.File(path, "a") as h:
        h["tracks"].create_dataset("source_track", data=h["tracks/track"][()].astype(np.int64) * 10 + 7)
    _, rows, _ = export(path, tmp_path, "associations")
    assert rows and all(int(r[4]) == int(r[3]) * 10 + 7 for r in rows)


def test_associations_round_trip_with_pandas(results, tmp_path):
    pd = pytest.importorskip("pandas")  # optional: python3-pandas
    _, _, out = export(results, tmp_path, "associations")
    table = pd.read_csv(out, float_precision="round_trip")  # pandas' default parser is not exact
    (a,) = trackassoc.read(str(results)).associations.values()
    # rebuild the K x S tuples and the costs from the table alone
    k = int(table["tuple"].max()) + 1
    col = {int(s): c for c, s in enumerate(a.sensor_ids)}
    tuples = np.full((k, len(col)), -1, np.int32)
    tuples[table["tuple"].to_numpy(), [col[s] for s in table["sensor"]]] = table["track"].to_numpy()
    linked = (a.tuples >= 0).any(axis=1)
    np.testing.assert_array_equal(tuples, a.tuples[:k])
    assert not linked[k:].any()
    cost = table.groupby("tuple")["cost"].first()
    assert cost.to_numpy().tobytes() == a.cost[:k][cost.index.to_numpy()].tobytes()
    # and it is the module's own table
    mine = a.to_pandas()
    pd.testing.assert_frame_equal(mine.reset_index(drop=True),
                                  table[["target", "tuple", "sensor", "track", "cost"]], check_dtype=False)


def test_unassociated(results, tmp_path):
    header, rows, _ = export(results, tmp_path, "unassociated")
    assert header == ["sensor", "track", "source_track", "first_t", "last_t", "reports"]
    (a,) = trackassoc.read(str(results)).associations.values()
    expected = sorted((s, int(k)) for s, tracks in a.unassociated.items() for k in tracks)
    assert sorted((int(r[0]), int(r[1])) for r in rows) == expected and expected
    t = trackassoc.read(str(results)).tracks
    for r in rows:
        mask = (t["sensor"] == int(r[0])) & (t["track"] == int(r[1]))
        assert float(r[3]) == t["t"][mask].min() and float(r[4]) == t["t"][mask].max()
        assert int(r[5]) == mask.sum()


def test_fused(results, tmp_path):
    header, rows, _ = export(results, tmp_path, "fused")
    assert header[:4] == ["tuple", "t", "x", "y"] and header[-2:] == ["sources", "truth"]
    with h5py.File(results, "r") as h:
        (g,) = h["fused"].values()
        state, cov, t = g["state"][()], g["cov"][()], g["t"][()]
    got = np.array([[float(x) for x in r] for r in rows])
    assert got.shape[0] == len(t) > 0
    assert got[:, 1].tobytes() == t.tobytes()
    assert got[:, 2:6].tobytes() == np.ascontiguousarray(state).tobytes()
    assert got[:, 6:16].tobytes() == np.ascontiguousarray(cov).tobytes()


def test_registration(simulated, tmp_path):
    # A /registration as associate writes it (registration on), every per-sensor dataset read back
    # from the CSV exactly: S rows -> one column, S x k -> NAME_0..NAME_k-1; others left out.
    path = tmp_path / "registered.h5"
    run_cli("associate", "--input", simulated("recorded_formation"), "--output", path)
    header, rows, _ = export(path, tmp_path, "registration")
    assert header[0] == "sensor"
    col = {n: i for i, n in enumerate(header)}
    with h5py.File(path, "r") as h:
        ids = h["sensors/id"][()]
        s = len(ids)
        per_sensor = {n: d[()] for n, d in h["registration"].items()
                      if isinstance(d, h5py.Dataset) and d.ndim in (1, 2) and d.shape[0] == s}
    assert [int(r[0]) for r in rows] == ids.tolist()
    expected = []
    for n, v in per_sensor.items():
        expected += [n] if v.ndim == 1 else ["%s_%d" % (n, k) for k in range(v.shape[1])]
    assert sorted(header[1:]) == sorted(expected)
    for i, r in enumerate(rows):
        for n, v in per_sensor.items():
            cells = [v[i]] if v.ndim == 1 else list(v[i])
            names = [n] if v.ndim == 1 else ["%s_%d" % (n, k) for k in range(v.shape[1])]
            for name, want in zip(names, cells):
                got = float(r[col[name]])
                assert got == float(want) or (np.isnan(got) and np.isnan(want)), (name, i)


def test_refusals(results, simulated, tmp_path):
    p = run_cli("export", "csv", "--input", results, "--output", tmp_path / "r.csv", "--what", "registration",
                check=False)
    assert p.returncode == 2 and "no /registration group" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and not (tmp_path / "r.csv").exists()
    p = run_cli("export", "csv", "--input", simulated("recorded_3s"), "--output", tmp_path / "a.csv", "--what",
                "associations", check=False)
    assert p.returncode == 2 and "/associations is empty" in p.stderr
    p = run_cli("export", "csv", "--input", results, "--output", tmp_path / "a.csv", "--what", "fused", "--name",
                "nosuch", check=False)
    assert p.returncode == 2 and "no /fused/nosuch" in p.stderr
    p = run_cli("export", "csv", "--input", results, "--output", tmp_path / "a.csv", "--what", "bogus",
                check=False)
    assert p.returncode == 2
