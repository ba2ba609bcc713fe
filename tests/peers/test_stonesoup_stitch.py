#!/usr/bin/python3
"""Unit tests of bench/stonesoup_stitch.py: the join scoring by hand, and (when Stone Soup imports
and the CLI is given) one end-to-end run on recorded_recycled whose join count for ours is checked
against the fragments and targets counted in the two files. Registered with CTest
(StoneSoupPeer.Stitch*); by hand from the repo root:
    TRACKASSOC_CLI=build/trackassoc /usr/bin/python3 tests/peers/test_stonesoup_stitch.py
"""
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "bench", "stonesoup_stitch.py")
sys.path.insert(0, os.path.join(ROOT, "bench"))
spec = importlib.util.spec_from_file_location("stonesoup_stitch", SCRIPT)
ss = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ss)


class Score(unittest.TestCase):
    def test_joins_by_hand(self):
        # Fragments 1-2-3 of target 5 (2 correct joins), 4 (target 6) after 7 (a false track, -1):
        # one false join; 8 alone.
        truth = {1: 5, 2: 5, 3: 5, 4: 6, 7: -1, 8: 6}
        self.assertEqual(ss.score([[1, 2, 3], [7, 4], [8]], truth), dict(joins=3, correct=2, false=1))
        self.assertEqual(ss.score([], truth), dict(joins=0, correct=0, false=0))


@unittest.skipUnless(os.environ.get("TRACKASSOC_CLI"), "TRACKASSOC_CLI not set")
class EndToEnd(unittest.TestCase):
    def test_recycled(self):
        import h5py
        cli = os.environ["TRACKASSOC_CLI"]
        with tempfile.TemporaryDirectory() as d:
            src, frag, ours, out = (os.path.join(d, n) for n in ("in.h5", "frag.h5", "ours.h5", "out.json"))
            subprocess.run([cli, "simulate", "--scenario", "recorded_recycled", "--seed", "1", "-o", src],
                           check=True, capture_output=True)
            subprocess.run([cli, "associate", "-i", src, "-o", frag, "--no-stitch"], check=True, capture_output=True)
            subprocess.run([cli, "associate", "-i", src, "-o", ours], check=True, capture_output=True)
            r = subprocess.run([sys.executable, SCRIPT, frag, ours, "--json", out], capture_output=True, text=True)
            if r.returncode == 3:
                self.skipTest("Stone Soup cannot be imported: " + r.stderr.strip())
            self.assertEqual(r.returncode, 0, r.stderr)
            res = json.load(open(out))
            # Ours: joins = fragments - the targets those fragments end up in (each join merges two).
            groups, merged = ss.groups_of(frag, None), ss.groups_of(ours, None)
            target_of = {k: t for t, keys in merged.items() for k in keys}
            after = {target_of[keys[0]] for keys in groups.values()}
            self.assertEqual(res["fragments"], len(groups))
            self.assertEqual(res["ours"]["joins"], len(groups) - len(after))
            for side in ("ours", "stonesoup"):
                s = res[side]
                self.assertEqual(s["correct"] + s["false"], s["joins"])
                self.assertLessEqual(s["joins"], res["fragments"] - 1)


if __name__ == "__main__":
    unittest.main()
