"""associate() releases the GIL (issue 32): while one Python thread is inside the engine, another
Python thread keeps running. No wall-time threshold: the check is that the second thread made
progress (ran Python code) between the moments the first one entered and left the call, which
cannot happen if the call holds the GIL, since a thread holding the GIL inside C++ never yields it."""
import threading
import time

import numpy as np

import trackassoc


def test_second_thread_runs_while_associate_runs(simulated):
    f = trackassoc.read(simulated("recorded_5s"))
    inside = threading.Event()
    window = {}
    results = []

    def worker():
        inside.set()
        window["enter"] = time.monotonic_ns()
        results.append(trackassoc.associate(f, threads=1))
        window["leave"] = time.monotonic_ns()

    ticks = []
    w = threading.Thread(target=worker)
    w.start()
    inside.wait()
    while w.is_alive():
        ticks.append(time.monotonic_ns())  # Python bytecode: needs the GIL
        time.sleep(0.0002)
    w.join()
    during = [t for t in ticks if window["enter"] < t < window["leave"]]
    # A GIL-holding call lets the main thread in only before the call starts and after it returns:
    # at most a tick or two at the edges. Many ticks mean the main thread ran while it was inside.
    assert len(during) >= 20, (len(during), (window["leave"] - window["enter"]) / 1e6)
    assert results[0].tuples.shape[0] > 0


def test_two_threads_associate_concurrently_with_the_same_results(simulated):
    f = trackassoc.read(simulated("recorded_3s"))
    expected = trackassoc.associate(f)
    out = [None, None]

    def run(i):
        out[i] = trackassoc.associate(f)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in out:
        np.testing.assert_array_equal(r.tuples, expected.tuples)
        assert r.cost.tobytes() == expected.cost.tobytes()
