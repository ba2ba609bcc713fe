"""The resampled Stone Soup peer (bench/stonesoup_resample.py, issue 29 item 5): on a hand-made
asynchronous two-sensor file Stone Soup as shipped links nothing and the resampled version links
both true pairs; a resampled state is the CV prediction worked out by hand. Skips when the Stone
Soup source is not at ../shared/peers/stonesoup-src or does not import (it is optional)."""
import importlib.util
import json
import os
from datetime import timedelta

import h5py
import numpy as np
import pytest

from conftest import SOURCE_DIR, STONESOUP_SRC

if not os.path.isdir(os.path.join(STONESOUP_SRC, "stonesoup")):
    pytest.skip("Stone Soup source not found at %s (optional)" % STONESOUP_SRC, allow_module_level=True)
os.environ.setdefault("STONESOUP_SRC", STONESOUP_SRC)

spec = importlib.util.spec_from_file_location("stonesoup_t2t", os.path.join(SOURCE_DIR, "bench", "stonesoup_t2t.py"))
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)
try:
    ss = bench.import_stonesoup()
except SystemExit:  # exit 3: a module is missing; the message is on stderr
    pytest.skip("Stone Soup does not import (optional)", allow_module_level=True)
resample = bench.resample

# Two sensors that never report at the same instant: sensor 1 every 2 s from 0.5 s (x.5 s),
# sensor 2 every 3 s from 0.2 s (x.2 s). Two targets 10 km apart, each seen by both sensors.
SENSORS = {1: (2.0, 0.5), 2: (3.0, 0.2)}
TARGETS = {0: ([0.0, 0.0], [150.0, 20.0]), 1: ([10000.0, 4000.0], [-120.0, 60.0])}
DURATION = 60.0
P = np.diag([100.0**2, 100.0**2, 5.0**2, 5.0**2])  # file order x, y, vx, vy


def write_async_file(path):
    rng = np.random.default_rng(7)
    rows = []
    for s, (period, offset) in SENSORS.items():
        for g, (x0, v) in TARGETS.items():
            for t in np.arange(offset, DURATION, period):
                pos = np.add(x0, np.multiply(v, t)) + rng.normal(0.0, 30.0, 2)
                rows.append((s, 10 * s + g, t, [*pos, *v], P[np.triu_indices(4)], g))
    with h5py.File(path, "w") as f:
        f.attrs["format"], f.attrs["schema_version"] = "trackassoc", np.int32(1)
        f["sensors/id"] = np.array(sorted(SENSORS), np.int32)
        for i, name in enumerate(["sensor", "track", "t", "state", "cov", "truth"]):
            dtype = np.int32 if name in ("sensor", "track", "truth") else np.float64
            f["tracks/" + name] = np.array([r[i] for r in rows], dtype)
        f["tracks"].attrs["state_layout"] = "x,y,vx,vy"


def test_shipped_links_nothing_resampled_links_both_pairs(tmp_path):
    src, out, js = tmp_path / "async.h5", tmp_path / "out.h5", tmp_path / "r.json"
    write_async_file(str(src))
    assert resample.grid_step(bench.load(str(src))) == 3.0  # the larger of the two periods
    assert bench.main([str(src), "--cov", "sum", "--json", str(js), "--write-into", str(out)]) == 0
    r = json.loads(js.read_text())
    for name in ("stonesoup-one2one", "stonesoup-counting"):  # as shipped: no shared timestamp
        assert r[name]["pairs_without_common_time"] == r[name]["candidate_pairs"] == 4, name
        assert (r[name]["linked_tuples"], r[name]["correct"], r[name]["targets"]) == (0, 0, 2), name
    for name in ("stonesoup-one2one-resampled", "stonesoup-counting-resampled"):
        assert r[name]["pairs_without_common_time"] == 0, name
        assert (r[name]["linked_tuples"], r[name]["correct"], r[name]["false_tuples"]) == (2, 2, 0), name
        assert r[name]["options"]["grid_step"] == 3.0 and r[name]["options"]["q"] == resample.DEFAULT_Q
    with h5py.File(out) as f:  # the tuples as /associations groups: (track of sensor 1, of sensor 2)
        assert f["associations/stonesoup-one2one/tuples"].shape == (4, 2)  # four singletons
        for name in ("stonesoup-one2one-resampled", "stonesoup-counting-resampled"):
            assert sorted(map(tuple, f["associations/" + name + "/tuples"][()])) == [(10, 20), (11, 21)]


def test_resampled_state_is_the_cv_prediction():
    q, step = 20.0, 3.0
    x = np.array([100.0, 7.0, -50.0, -3.0])  # Stone Soup order x, vx, y, vy
    p = np.array([[400.0, 10.0, 30.0, 2.0], [10.0, 4.0, 1.0, 0.5],
                  [30.0, 1.0, 900.0, 15.0], [2.0, 0.5, 15.0, 9.0]])
    reports = [1.0, 2.5, 12.0]  # a 9.5 s silence after 2.5 s: longer than the step
    track = ss["Track"]([ss["GS"](ss["SV"](x + i), ss["Cov"](p), timestamp=bench.EPOCH + timedelta(seconds=t))
                         for i, t in enumerate(reports)])
    predictor = resample.make_predictor(ss, 2, q)
    out, times, calls = resample.resample_tracks({(0, 1): track}, ss, predictor, step, bench.EPOCH)
    # grid 3, 6, 9, 12 within [1, 12]; 6 and 9 are more than one step after the 2.5 s report
    seconds = [(w - bench.EPOCH).total_seconds() for w in times[(0, 1)]]
    assert seconds == [3.0, 12.0] and calls == 2
    state = out[(0, 1)].states[0]  # from the report at 2.5 s (state x + 1), dt = 0.5 s
    dt = 0.5
    f1 = np.array([[1.0, dt], [0.0, 1.0]])
    q1 = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    f, qq = np.kron(np.eye(2), f1), np.kron(np.eye(2), q1)
    expected_x = x + 1 + np.array([(x[1] + 1) * dt, 0.0, (x[3] + 1) * dt, 0.0])  # x + v dt
    np.testing.assert_allclose(np.asarray(state.state_vector, float)[:, 0], expected_x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(state.covar, float), f @ p @ f.T + qq, rtol=1e-14, atol=1e-12)
    at_report = out[(0, 1)].states[1]  # at 12 s a report exists: dt = 0, the report itself
    np.testing.assert_allclose(np.asarray(at_report.state_vector, float)[:, 0], x + 2, atol=1e-12)
    np.testing.assert_allclose(np.asarray(at_report.covar, float), p, atol=1e-12)
