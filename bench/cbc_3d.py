#!/usr/bin/python3
"""MILP peer for the exact 3-D assignment solver: CBC (Debian coinor-cbc) on the Balas–Saltzman
instances that bench_3d_solvers' BM_ExactBalasSaltzman solves.

Model: binary x_ijk for every (i, j, k); minimise sum b_ijk x_ijk; sum_jk x_ijk = 1 for each i, and
likewise for each j and each k (the axial 3-D assignment, seed 000 Eq. 5-6). Written as a CPLEX LP
file and solved by `cbc FILE -threads T -sec LIMIT -solve -solu OUT`; the wall time includes
CBC's reading of the file (small next to the solve for n >= 14).

If cbc is not installed the script says so and exits 0 (it is a benchmark peer, not a test
dependency): apt-get install coinor-cbc.

Usage: /usr/bin/python3 bench/cbc_3d.py [--sizes 14,16,...] [--replicas 1-5] [--threads 1] [--time-limit 300]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
BS = os.path.join(HERE, "..", "..", "shared", "benchmarks", "3dap", "balas-saltzman")


def read_instance(path):
    with open(path) as f:
        v = f.read().split()
    s, n1, n2, n3 = int(v[0]), int(v[1]), int(v[2]), int(v[3])
    assert s == 3
    c = [float(x) for x in v[4:]]
    assert len(c) == n1 * n2 * n3, path
    return n1, n2, n3, c


def write_lp(path, n1, n2, n3, c):
    name = lambda i, j, k: f"x{i}_{j}_{k}"
    with open(path, "w") as f:
        f.write("Minimize\n obj:")
        for i in range(n1):
            for j in range(n2):
                for k in range(n3):
                    f.write(f" + {c[(i * n2 + j) * n3 + k]:g} {name(i, j, k)}")
                f.write("\n")
        f.write("Subject To\n")
        for i in range(n1):
            f.write(f" a{i}: " + " + ".join(name(i, j, k) for j in range(n2) for k in range(n3)) + " = 1\n")
        for j in range(n2):
            f.write(f" b{j}: " + " + ".join(name(i, j, k) for i in range(n1) for k in range(n3)) + " = 1\n")
        for k in range(n3):
            f.write(f" c{k}: " + " + ".join(name(i, j, k) for i in range(n1) for j in range(n2)) + " = 1\n")
        f.write("Binary\n")
        for i in range(n1):
            for j in range(n2):
                f.write(" " + " ".join(name(i, j, k) for k in range(n3)) + "\n")
        f.write("End\n")


def solve(cbc, lp, sol, threads, limit):
    t0 = time.perf_counter()
    out = subprocess.run([cbc, lp, "-threads", str(threads), "-sec", str(limit), "-solve", "-solu", sol],
                         capture_output=True, text=True)
    wall = time.perf_counter() - t0
    status, obj = "unknown", None
    if os.path.exists(sol):
        with open(sol) as f:
            first = f.readline()
        status = first.split()[0] if first.split() else "unknown"
        if "objective value" in first:
            obj = float(first.rsplit("objective value", 1)[1].split()[0])
    return wall, status, obj, out.returncode


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", default="14,16,18,20,22,24,26")
    p.add_argument("--replicas", default="1-5")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--time-limit", type=float, default=300.0)
    p.add_argument("--json", help="write the results here")
    args = p.parse_args()
    cbc = shutil.which("cbc")
    if cbc is None:
        print("cbc_3d: cbc not installed (apt-get install coinor-cbc); skipping the MILP peer")
        return 0
    lo, hi = map(int, args.replicas.split("-"))
    optima = {}
    with open(os.path.join(BS, "bs.opt")) as f:
        for line in f:
            if line.split():
                optima[line.split()[0]] = float(line.split()[1])
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in map(int, args.sizes.split(",")):
            times = []
            for r in range(lo, hi + 1):
                name = f"bs.{n}.{r}"
                n1, n2, n3, c = read_instance(os.path.join(BS, name + ".txt"))
                lp, sol = os.path.join(tmp, name + ".lp"), os.path.join(tmp, name + ".sol")
                write_lp(lp, n1, n2, n3, c)
                wall, status, obj, rc = solve(cbc, lp, sol, args.threads, args.time_limit)
                ok = status == "Optimal" and obj is not None and abs(obj - optima[name]) < 1e-6
                times.append(wall)
                results.append({"instance": name, "wall_s": wall, "status": status, "objective": obj,
                                "known_optimum": optima[name], "matches_optimum": ok})
                print(f"cbc {name:9s} threads {args.threads}  {wall:8.3f} s  {status:10s} objective {obj}  "
                      f"known {optima[name]:g}  {'ok' if ok else 'MISMATCH/UNSOLVED'}", flush=True)
            print(f"cbc n={n:2d}: median {statistics.median(times):.3f} s per instance", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
