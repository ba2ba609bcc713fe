"""Shared fixtures of the Python module's pytest suite (tests/python/, run by ctest: python.*).

The module comes from PYTHONPATH (ctest sets build/python); the command line from $TRACKASSOC_CLI
(default build/trackassoc). Track files are made once per session with `trackassoc simulate`
(the recorded family, seed 1). Optional: Stone Soup (../shared/peers/stonesoup-src) and pandas;
the tests that need them skip without them. Everything else fails when the module is broken."""
import os
import subprocess

import pytest

import trackassoc  # noqa: F401  (a broken module fails every test file at collection)

SOURCE_DIR = os.environ.get("TRACKASSOC_SOURCE_DIR",
                            os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
CLI = os.environ.get("TRACKASSOC_CLI", os.path.join(SOURCE_DIR, "build", "trackassoc"))
SHARED_DIR = os.environ.get("TRACKASSOC_SHARED_DIR", os.path.join(SOURCE_DIR, "..", "shared"))
STONESOUP_SRC = os.path.join(SHARED_DIR, "peers", "stonesoup-src")


def run_cli(*args, check=True):
    """Runs the command line; returns the CompletedProcess (text)."""
    p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError("trackassoc %s: exit %d\n%s%s" % (" ".join(map(str, args)), p.returncode, p.stdout,
                                                                p.stderr))
    return p


@pytest.fixture(scope="session")
def simulated(tmp_path_factory):
    """scenario name -> path of `trackassoc simulate --scenario NAME --seed 1` (made on first use)."""
    folder = tmp_path_factory.mktemp("sim")
    made = {}

    def get(name):
        if name not in made:
            path = folder / (name + ".h5")
            run_cli("simulate", "--scenario", name, "--seed", 1, "--output", path)
            made[name] = str(path)
        return made[name]
    return get
