#!/usr/bin/python3
"""Peer benchmark: scipy.optimize.linear_sum_assignment on the matrices of bench/lap_matrices.hpp.

The matrices are regenerated here bit-for-bit: CounterRng (kernels/core/random.hpp) is SplitMix64 over
a stream key, re-implemented with numpy uint64 arithmetic (wrap-around is the point). Prints, per
matrix, the median wall and CPU (process) time of `--repetitions` solves and the optimum, to compare
with the Time / CPU columns and the `objective` counter of bench_lap. Run with Debian's python3-scipy: /usr/bin/python3 bench/lap_scipy.py
"""
import argparse
import json
import sys
import time

import numpy as np

try:
    from scipy.optimize import linear_sum_assignment
except ImportError:
    print("lap_scipy: scipy not installed (apt-get install python3-scipy); skipping", file=sys.stderr)
    sys.exit(0)

M64 = (1 << 64) - 1
SEED = 20261123


def mix(z):
    z = np.asarray(z, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))


def mix_int(z):
    return int(mix(np.uint64(z & M64)))


def stream_key(seed, a=0, b=0, c=0):
    k = mix_int((seed + 0x9E3779B97F4A7C15) & M64)
    k = mix_int(k ^ ((a + 0x632BE59BD9B4E019) & M64))
    k = mix_int(k ^ ((b + 0x8CB92BA72F3D8DD7) & M64))
    k = mix_int(k ^ ((c + 0xD1B54A32D192ED03) & M64))
    return k


def uniforms(seed, a, b, count):
    key = np.uint64(stream_key(seed, a, b))
    ctr = np.arange(1, count + 1, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = mix(key + ctr * np.uint64(0x9E3779B97F4A7C15))
    return (z >> np.uint64(11)).astype(np.float64) * 2.0**-53


def uniform_matrix(n):
    return uniforms(SEED, n, 0, n * n).reshape(n, n)


def geometric_matrix(n):
    a = uniforms(SEED, n, 1, 2 * n).reshape(n, 2)
    b = uniforms(SEED, n, 2, 2 * n).reshape(n, 2)
    d = a[:, None, :] - b[None, :, :]
    return d[:, :, 0] * d[:, :, 0] + d[:, :, 1] * d[:, :, 1]


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--sizes", default="100,1000,2000")
    p.add_argument("--repetitions", type=int, default=5)
    p.add_argument("--json", help="write results here")
    args = p.parse_args()
    out = []
    for kind, gen in (("uniform", uniform_matrix), ("geometric", geometric_matrix)):
        for n in map(int, args.sizes.split(",")):
            c = gen(n)
            times, cpu = [], []
            for _ in range(args.repetitions):
                t0, p0 = time.perf_counter(), time.process_time()
                r, col = linear_sum_assignment(c)
                times.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - p0)
            obj = float(c[r, col].sum())
            med, med_cpu = float(np.median(times)), float(np.median(cpu))
            out.append({"kind": kind, "n": n, "median_ms": med * 1e3, "median_cpu_ms": med_cpu * 1e3, "objective": obj})
            print(f"scipy linear_sum_assignment {kind:9s} n={n:5d}  median {med*1e3:9.3f} ms  "
                  f"cpu {med_cpu*1e3:9.3f} ms  objective {obj:.12g}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
