#!/usr/bin/python3
"""MILP peer for the exact 3-D assignment solver: CBC (Debian coinor-cbc) on the Balas–Saltzman
instances that bench_3d_solvers' BM_ExactBalasSaltzman solves (--set balas-saltzman, the default)
or the DecompLib ap3 instances of BM_ExactDecompLib (--set decomplib).

Model: binary x_ijk for every (i, j, k); minimise sum b_ijk x_ijk; sum_jk x_ijk = 1 for each i, and
likewise for each j and each k (the axial 3-D assignment, seed 000 Eq. 5-6). Written as a CPLEX LP
file and solved by `cbc FILE -threads T -sec LIMIT -solve -solu OUT`; the wall time includes
CBC's reading of the file (small next to the solve for n >= 14).

From CBC's log: the root bound after its cuts ("At root node, ... changed objective from A to B")
and the search nodes ("took ... iterations and N nodes").

--ours FILE merges a Google Benchmark JSON of bench_3d_solvers' BM_ExactDecompLib (its
--benchmark_out) into one table, instance by instance: time to proof, nodes and root bound of
both, and the ratio. The README row "exact branch and bound" is this table, from one run:

  /usr/bin/python3 bench/cbc_3d.py --set decomplib --json /tmp/cbc.json
  build/bench_3d_solvers --benchmark_filter=BM_ExactDecompLib \
      --benchmark_out=/tmp/ours.json --benchmark_out_format=json
  /usr/bin/python3 bench/cbc_3d.py --set decomplib --cbc-results /tmp/cbc.json --ours /tmp/ours.json

(the last call only merges the two, back to back; --ours without --cbc-results runs CBC and merges
as it goes).

If cbc is not installed the script says so and exits 0 (it is a benchmark peer, not a test
dependency): apt-get install coinor-cbc.

Usage: /usr/bin/python3 bench/cbc_3d.py [--set balas-saltzman|decomplib] [--sizes 14,16,...]
       [--replicas 1-5] [--threads 1] [--time-limit 300] [--json OUT] [--ours BENCH_JSON]
       [--cbc-results CBC_JSON]
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SETS = {  # folder, instance prefix, optima file, default sizes, default replicas
    "balas-saltzman": ("balas-saltzman", "bs", "bs.opt", "14,16,18,20,22,24,26", "1-5"),
    "decomplib": ("decomplib", "ap3", "ap3.opt", "5,10,20,30,40,50", "1-10"),
}
ROOT = os.path.join(HERE, "..", "..", "shared", "benchmarks", "3dap")


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
    root = re.search(r"At root node, .* changed objective from (\S+) to (\S+)", out.stdout)
    nodes = re.search(r"took \d+ iterations and (\d+) nodes", out.stdout)
    # The LP relaxation CBC solves first (CLP), with its time: the peer of the Lagrangian bound.
    lp = re.search(r"Continuous objective value is (\S+) - (\S+) seconds", out.stdout)
    lp_bound, lp_s = (float(lp.group(1)), float(lp.group(2))) if lp else (None, None)
    root_bound = float(root.group(2)) if root else lp_bound  # no cut changed it: the LP bound
    nodes = int(nodes.group(1)) if nodes else None
    status, obj = "unknown", None
    if os.path.exists(sol):
        with open(sol) as f:
            first = f.readline()
        status = first.split()[0] if first.split() else "unknown"
        if "objective value" in first:
            obj = float(first.rsplit("objective value", 1)[1].split()[0])
    return wall, status, obj, out.returncode, root_bound, nodes, lp_bound, lp_s


def read_ours(path):
    """BM_ExactDecompLib/n/r rows of a Google Benchmark JSON → {instance: row}."""
    with open(path) as f:
        data = json.load(f)
    ours = {}
    for b in data["benchmarks"]:  # one iteration row, or the median of --benchmark_repetitions
        m = re.match(r"BM_ExactDecompLib/(\d+)/(\d+)", b["name"])
        if m and (b.get("run_type", "iteration") == "iteration" or b.get("aggregate_name") == "median"):
            scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b.get("time_unit", "ns")]
            ours[f"ap3.{m.group(1)}.{m.group(2)}"] = {"wall_s": b["real_time"] * scale, "nodes": b["nodes"],
                                                       "root_bound": b["root_bound"], "optimal": b["optimal"]}
    return ours


def read_cbc_results(path):
    """A --json of an earlier run, or its printed log (the lines of instances it finished)."""
    with open(path) as f:
        text = f.read()
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        pass
    rows = []
    pat = re.compile(r"cbc (\S+)\s+threads \d+\s+(\S+) s\s+(\S+)\s+objective (\S+)\s+known (\S+)\s+root (\S+)\s+"
                     r"nodes (\S+)\s+(\S+)")
    for line in text.splitlines():
        m = pat.match(line)
        if m:
            num = lambda x: None if x == "None" else float(x)
            rows.append({"instance": m.group(1), "wall_s": float(m.group(2)), "status": m.group(3),
                         "objective": num(m.group(4)), "known_optimum": float(m.group(5)),
                         "root_bound": num(m.group(6)), "nodes": None if m.group(7) == "None" else int(m.group(7)),
                         "matches_optimum": m.group(8) == "ok"})
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--set", choices=sorted(SETS), default="balas-saltzman")
    p.add_argument("--sizes")
    p.add_argument("--replicas")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--time-limit", type=float, default=300.0)
    p.add_argument("--json", help="write the results here")
    p.add_argument("--ours", help="bench_3d_solvers JSON (BM_ExactDecompLib) to merge into one table")
    p.add_argument("--cbc-results", help="a --json of an earlier run of this script: merge it with --ours "
                   "instead of running CBC (both measured back to back)")
    args = p.parse_args()
    folder, prefix, opt_file, sizes, replicas = SETS[args.set]
    sizes, replicas = args.sizes or sizes, args.replicas or replicas
    cbc = shutil.which("cbc")
    if cbc is None:
        print("cbc_3d: cbc not installed (apt-get install coinor-cbc); skipping the MILP peer")
        return 0
    ours = read_ours(args.ours) if args.ours else {}
    lo, hi = map(int, replicas.split("-"))
    optima = {}
    with open(os.path.join(ROOT, folder, opt_file)) as f:
        for line in f:
            if line.split():
                optima[line.split()[0]] = float(line.split()[1])
    results = []
    if args.cbc_results:
        results = read_cbc_results(args.cbc_results)
        for row in results:
            if row["instance"] in ours:
                o = row["ours"] = ours[row["instance"]]
                print(f"{row['instance']:10s} cbc {row['wall_s']:8.3f} s  nodes {row['nodes']}  root {row['root_bound']}  "
                      f"{'ok' if row['matches_optimum'] else 'UNSOLVED'}  | ours {o['wall_s']:8.3f} s  nodes "
                      f"{o['nodes']:g}  root {o['root_bound']:g}  {'proven' if o['optimal'] == 1 else 'NOT PROVEN'}  "
                      f"cbc/ours {row['wall_s'] / o['wall_s']:6.1f}x  (optimum {row['known_optimum']:g})")
        sizes = ",".join(sorted({r["instance"].split(".")[1] for r in results}, key=int))
    with tempfile.TemporaryDirectory() as tmp:
        for n in (map(int, sizes.split(",")) if not args.cbc_results else []):
            times = []
            for r in range(lo, hi + 1):
                name = f"{prefix}.{n}.{r}"
                n1, n2, n3, c = read_instance(os.path.join(ROOT, folder, name + ".txt"))
                lp, sol = os.path.join(tmp, name + ".lp"), os.path.join(tmp, name + ".sol")
                write_lp(lp, n1, n2, n3, c)
                wall, status, obj, rc, root_bound, nodes, lp_bound, lp_s = solve(cbc, lp, sol, args.threads, args.time_limit)
                ok = status == "Optimal" and obj is not None and abs(obj - optima[name]) < 1e-6
                times.append(wall)
                row = {"instance": name, "wall_s": wall, "status": status, "objective": obj,
                       "known_optimum": optima[name], "matches_optimum": ok, "root_bound": root_bound,
                       "nodes": nodes, "lp_bound": lp_bound, "lp_s": lp_s}
                results.append(row)
                line = (f"cbc {name:10s} threads {args.threads}  {wall:8.3f} s  {status:10s} objective {obj}  "
                        f"known {optima[name]:g}  root {root_bound}  nodes {nodes}  "
                        f"{'ok' if ok else 'MISMATCH/UNSOLVED'}")
                if name in ours:
                    o = ours[name]
                    row["ours"] = o
                    line += (f"  | ours {o['wall_s']:8.3f} s  nodes {o['nodes']:g}  root {o['root_bound']:g}  "
                             f"{'proven' if o['optimal'] == 1 else 'NOT PROVEN'}  cbc/ours {wall / o['wall_s']:6.1f}x")
                print(line, flush=True)
            print(f"cbc n={n:2d}: median {statistics.median(times):.3f} s per instance", flush=True)
    if ours:
        print("\n| n | instances proven (ours / CBC) | ours: median [max] s | CBC: median [max] s | "
              "ratio CBC/ours: min–median | root bound = optimum (ours / CBC) |")
        print("|---|---|---|---|---|---|")
        for n in map(int, sizes.split(",")):
            rows = [x for x in results if x["instance"].split(".")[1] == str(n) and "ours" in x]
            if not rows:
                continue
            ot = [x["ours"]["wall_s"] for x in rows]
            ct = [x["wall_s"] for x in rows]
            ratio = sorted(c / o for c, o in zip(ct, ot))
            ours_ok = sum(x["ours"]["optimal"] == 1 for x in rows)
            cbc_ok = sum(bool(x["matches_optimum"]) for x in rows)
            ours_tight = sum(x["ours"]["root_bound"] >= x["known_optimum"] - 1e-6 for x in rows)
            cbc_tight = sum(x["root_bound"] is not None and x["root_bound"] >= x["known_optimum"] - 1e-6
                            for x in rows)
            print(f"| {n} | {ours_ok} / {cbc_ok} of {len(rows)} | {statistics.median(ot):.3f} [{max(ot):.3f}] | "
                  f"{statistics.median(ct):.3f} [{max(ct):.3f}] | {ratio[0]:.1f}–{statistics.median(ratio):.1f}× | "
                  f"{ours_tight} / {cbc_tight} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
