#!/usr/bin/python3
"""Unit tests of bench/stonesoup_t2t.py: chaining, scoring, and (when Stone Soup imports) one
end-to-end run on a small synthetic synchronous file. Registered with CTest
(StoneSoupPeer.*); by hand from the repo root:  /usr/bin/python3 tests/peers/test_stonesoup_t2t.py
"""
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "bench", "stonesoup_t2t.py")
spec = importlib.util.spec_from_file_location("stonesoup_t2t", SCRIPT)
st = importlib.util.module_from_spec(spec)
spec.loader.exec_module(st)


class ChainAndScore(unittest.TestCase):
    def test_schedule(self):
        self.assertEqual(st.pair_schedule(4), [(0, 1), (1, 2), (2, 3), (0, 2), (1, 3), (0, 3)])

    def test_no_same_sensor_merge(self):
        c = st.Chain([(0, 1), (1, 1), (1, 2)])
        self.assertTrue(c.link((0, 1), (1, 1)))
        self.assertFalse(c.link((0, 1), (1, 2)))  # would hold two tracks of sensor 1
        self.assertEqual(c.tuples(2).tolist(), [[1, 1], [-1, 2]])

    def test_score_rule(self):
        truth = {(0, 1): 7, (1, 1): 7, (2, 1): 7,   # target 7: correct
                 (0, 2): 8, (1, 2): 8,              # target 8: split -> missed
                 (0, 3): 9, (1, 3): -1, (2, 3): 9}  # target 9 grouped with a false track
        tuples = np.array([[1, 1, 1], [2, -1, -1], [-1, 2, -1], [3, 3, 3]], np.int32)
        m = st.score(tuples, truth)
        self.assertEqual((m["targets"], m["correct"], m["missed"], m["false"]), (3, 1, 1, 1))
        self.assertEqual(m["false_tuples"], 1)


def write_synthetic(path, sensors=3, targets=4):
    import h5py
    rng = np.random.default_rng(0)
    rows = []
    for s in range(sensors):
        for g in range(targets):
            for i in range(30):
                x = np.array([800 * g + 10 * i, -300 * g, 10, 0.0]) + rng.normal(0, [15, 15, 1, 1])
                cov = np.diag([225, 225, 1, 1.0])[np.triu_indices(4)]
                rows.append((s + 1, 3 * g + s, float(i), x, cov, g))
    with h5py.File(path, "w") as f:
        f.attrs["format"], f.attrs["schema_version"] = "trackassoc", np.int32(1)
        f["sensors/id"] = np.arange(1, sensors + 1, dtype=np.int32)
        for i, name in enumerate(["sensor", "track", "t", "state", "cov", "truth"]):
            dtype = np.int32 if name in ("sensor", "track", "truth") else np.float64
            f["tracks/" + name] = np.array([r[i] for r in rows], dtype)
        f["tracks"].attrs["state_layout"] = "x,y,vx,vy"


class EndToEnd(unittest.TestCase):
    def test_synchronous_is_correct(self):
        with tempfile.TemporaryDirectory() as d:
            src, out, js = (os.path.join(d, n) for n in ("in.h5", "out.h5", "r.json"))
            write_synthetic(src)
            p = subprocess.run([sys.executable, SCRIPT, src, "--json", js, "--write-into", out],
                               capture_output=True, text=True)
            if p.returncode == 3:
                self.skipTest(p.stderr.strip())
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(js) as f:
                r = json.load(f)
            for name in ("stonesoup-one2one", "stonesoup-counting"):
                self.assertEqual(r[name]["correct_rate"], 1.0, name)
                self.assertEqual(r[name]["pairs_without_common_time"], 0)
            import h5py
            with h5py.File(out) as f:
                g = f["associations/stonesoup-one2one"]
                self.assertEqual(g["tuples"].shape, (4, 3))
                self.assertEqual(g.attrs["termination"], "peer")


if __name__ == "__main__":
    unittest.main()
