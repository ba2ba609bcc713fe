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
    associated, out = folder / "a.h5", folder / "f.h5"
    run_cli("associate", "--input", simulated("recorded_formation"), "--output", associated)
    run_cli("fuse", "--input", associated, "--rule", "naive", "--output", out)
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


def test_a_malformed_registration_is_refused(results, tmp_path):
    """A /registration group that is not the schema's (no reference_sensor attribute) is refused by the
    reader in one line naming the group and what is missing, and nothing is written."""
    path = tmp_path / "registered.h5"
    shutil.copyfile(results, path)
    with h5py.File(path, "a") as h:
        s = len(h["sensors/id"])
        del h["registration"]  # the default pipeline's own; replaced by a hand-made one
        g = h.create_group("registration")
        g.create_dataset("bias_range", data=np.arange(s) * 1.5)
    out = tmp_path / "r.csv"
    p = run_cli("export", "csv", "--input", path, "--output", out, "--what", "registration", check=False)
    assert p.returncode == 2 and "/registration/reference_sensor: missing attribute" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and not out.exists()


def test_registration_of_associate(simulated, tmp_path):
    """recorded_bias: the registration the default pipeline estimated, one row per sensor, each column the
    /registration dataset of that name (estimates and standard errors), exact numbers."""
    out = tmp_path / "bias.h5"
    run_cli("associate", "--input", simulated("recorded_bias"), "--output", out)
    header, rows, _ = export(out, tmp_path, "registration")
    with h5py.File(out, "r") as h:
        g = h["registration"]
        assert g.attrs["applied"] == 1
        names = [n for n in g if g[n].ndim == 1 and len(g[n]) == len(h["sensors/id"])]
        assert set(header) >= set(names) and "range_bias" in header and "azimuth_bias_se" in header
        col = {n: i for i, n in enumerate(header)}
        for n in names:
            got = np.array([float(r[col[n]]) for r in rows])
            np.testing.assert_array_equal(got, g[n][()].astype(np.float64))


def test_refusals(results, simulated, tmp_path):
    p = run_cli("export", "csv", "--input", simulated("recorded_3s"), "--output", tmp_path / "r.csv", "--what",
                "registration", check=False)
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
