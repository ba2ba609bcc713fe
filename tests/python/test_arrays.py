"""Bad arrays are refused with one-line ValueErrors naming the column (and row), by the readers'
own checks (io/track_validation.hpp) where the content is at fault (issue 32)."""
import numpy as np
import pytest

import trackassoc


def two_sensor_tracks():
    """Two sensors, two targets on straight lines, one track each per sensor, 6 reports at 1 s."""
    rows = []
    for s in (0, 1):
        for k, (x0, vx) in enumerate([(0.0, 10.0), (5000.0, -10.0)]):
            for i in range(6):
                t = float(i)
                rows.append((s, k, t, [x0 + vx * t + 3.0 * s, 100.0 * k, vx, 0.0], k))
    n = len(rows)
    cov = np.tile(np.array([25.0, 0, 0, 0, 25.0, 0, 0, 4.0, 0, 4.0]), (n, 1))  # packed upper triangle
    return {"sensor": np.array([r[0] for r in rows], np.int32), "track": np.array([r[1] for r in rows], np.int32),
            "t": np.array([r[2] for r in rows]), "state": np.array([r[3] for r in rows]), "cov": cov,
            "truth": np.array([r[4] for r in rows], np.int32)}


def test_good_arrays_associate_the_two_targets():
    a = trackassoc.associate(two_sensor_tracks())
    # worked out by hand: the same target's tracks are 3 m apart (sigma 5 m), the targets 5 km
    assert sorted(map(tuple, a.tuples.tolist())) == [(0, 0), (1, 1)]
    assert list(a.sensor_ids) == [0, 1]
    assert all(len(v) == 0 for v in a.unassociated.values())
    assert trackassoc.evaluate(a)["correct_rate"] == 1.0
    f = trackassoc.tracks(two_sensor_tracks())
    assert f.sensors["period"].tolist() == [1.0, 1.0]  # the median report interval


def bad(column, value):
    t = two_sensor_tracks()
    t[column] = value(t[column]) if callable(value) else value
    return t


def nan_at(a, row, col=None):
    a = a.copy()
    if col is None:
        a[row] = np.nan
    else:
        a[row, col] = np.nan
    return a


def not_pd(cov):
    cov = cov.copy()
    cov[3, 0] = -1.0  # P(0,0) < 0
    return cov




@pytest.mark.parametrize("tracks, message", [
    (bad("state", lambda s: s[:, :3]), "/tracks/state: expected N x 4"),
    (bad("cov", lambda c: c[:, :9]), "/tracks/cov: expected N x 10"),
    (bad("t", lambda t: t[:-1]), "/tracks/t: expected N = 24 values"),
    (bad("t", lambda t: t.astype(str)), "/tracks/t: expected real numbers, found dtype <U"),
    (bad("sensor", lambda s: s.astype(np.float64)), "/tracks/sensor: expected integers, found dtype float64"),
    (bad("track", lambda k: k.astype(np.int64) + 2**40), "/tracks/track: row 0: expected an int32 value"),
    (bad("state", lambda s: nan_at(s, 5, 2)), "/tracks/state"),
    (bad("t", lambda t: nan_at(t, 7)), "/tracks/t: row 7"),
    (bad("cov", not_pd), "/tracks/cov: row 3"),
    (bad("cov", lambda c: np.zeros((24, 4, 3))), "/tracks/cov: expected N x 10"),
    ({"sensor": [0], "track": [0], "t": [0.0], "cov": np.eye(4)[None]}, "/tracks/state: expected this column"),
    ([1, 2, 3], "expected a dict of arrays or a structured numpy array"),
])
def test_bad_arrays(tracks, message):
    with pytest.raises(ValueError) as e:
        trackassoc.associate(tracks, sensors=[0, 1])
    assert message in str(e.value)
    assert str(e.value).startswith("tracks: ")
    assert "\n" not in str(e.value)


def test_non_pd_message_is_the_readers():
    """The message for a non-positive-definite covariance is the file reader's (same check)."""
    with pytest.raises(ValueError) as e:
        trackassoc.associate(bad("cov", not_pd))
    assert "tracks: /tracks/cov: row 3:" in str(e.value)
    assert "positive" in str(e.value)


def test_asymmetric_full_covariance():
    t = two_sensor_tracks()
    full = np.tile(np.diag([25.0, 25.0, 4.0, 4.0]), (24, 1, 1))
    full[2, 0, 1] = 1.0  # (0,1) != (1,0)
    t["cov"] = full
    with pytest.raises(ValueError, match=r"/tracks/cov: row 2: expected a symmetric matrix"):
        trackassoc.associate(t)


def test_duplicate_rows():
    t = two_sensor_tracks()
    for k in ("sensor", "track", "t", "state", "cov", "truth"):
        t[k] = np.concatenate([t[k], t[k][:1]])
    with pytest.raises(ValueError, match="/tracks"):
        trackassoc.associate(t)


def test_bad_sensors():
    with pytest.raises(ValueError, match="sensors"):
        trackassoc.associate(two_sensor_tracks(), sensors={"id": [0, 1], "period": [1.0]})
    with pytest.raises(ValueError, match="/sensors"):
        trackassoc.associate(two_sensor_tracks(), sensors={"id": [0, 0]})  # ids not unique (check_sensors)
    with pytest.raises(ValueError, match="sensor 2"):
        trackassoc.associate(two_sensor_tracks(), sensors=[0, 1, 2])  # sensor 2 has no track: no period
    with pytest.raises(ValueError, match="threads"):
        trackassoc.associate(two_sensor_tracks(), threads=0)


def test_arrays_written_and_read_back(tmp_path):
    """write() of arrays (with their association) gives a file the C++ reader takes back unchanged."""
    t = two_sensor_tracks()
    a = trackassoc.associate(t, name="hand")
    out = tmp_path / "arrays.h5"
    trackassoc.write(str(out), t, associations=[a])
    back = trackassoc.read(str(out))
    for k in ("sensor", "track", "t", "state", "cov", "truth"):
        assert back.tracks[k].tobytes() == np.ascontiguousarray(t[k], dtype=back.tracks[k].dtype).tobytes(), k
    assert back.sensors["id"].tolist() == [0, 1] and back.sensors["period"].tolist() == [1.0, 1.0]
    np.testing.assert_array_equal(back.associations["hand"].tuples, a.tuples)
    assert trackassoc.evaluate(back.associations["hand"])["correct_rate"] == 1.0
