#!/usr/bin/python3
"""The performance table of docs/performance.md from one scripts/bench.sh run: every row is ours against a peer
measured in the same run (an outside tool on the same input, or the naive version of the same
kernel), and the parallel kernels at 1 and 2 threads, with the ratios. Medians of bench.sh's five
repetitions (wall time; Google Benchmark's real_time); the peers' medians as their scripts report
them. A row whose inputs are missing says "not run" rather than dropping out.

Usage: /usr/bin/python3 scripts/bench_report.py [bench-results]   (markdown on stdout)
"""
import glob
import json
import math
import os
import re
import statistics
import sys

UNIT = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def load_benchmarks(folder):
    """{key: {"s": median wall seconds, "cpu_s": ..., counters...}} over every bench_*.json; key is the
    run name without /real_time, /manual_time and iterations:N (e.g. BM_Lap/uniform/1000)."""
    rows = {}
    for path in sorted(glob.glob(os.path.join(folder, "bench_*.json"))):
        try:
            with open(path) as f:
                data = json.load(f)
        except json.JSONDecodeError:
            print(f"bench_report: {path} is incomplete (a run in progress?); its rows say not run", file=sys.stderr)
            continue
        for b in data.get("benchmarks", []):
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            key = "/".join(p for p in b.get("run_name", b["name"]).split("/")
                           if p not in ("real_time", "manual_time") and not p.startswith("iterations:"))
            row = {k: v for k, v in b.items() if isinstance(v, (int, float))}
            row["s"] = b["real_time"] * UNIT[b.get("time_unit", "ns")]
            row["cpu_s"] = b["cpu_time"] * UNIT[b.get("time_unit", "ns")]
            rows[key] = row
    return rows


def load_json(folder, name):
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def fmt(s):
    if s is None:
        return "not run"
    if s >= 1.0:
        return f"{s:.2f} s"
    if s >= 1e-3:
        return f"{s * 1e3:.3g} ms"
    return f"{s * 1e6:.3g} µs"


def ratio(a, b):
    """a / b as '2.3×', or '—'."""
    if a is None or b is None or b <= 0:
        return "—"
    r = a / b
    return f"{r:.3g}×" if r < 100 else f"{r:.0f}×"


class Table:
    HEAD = ("| kernel | input | ours, 1 thread | 2 threads | 2 vs 1 | peer (same run) | peer | peer / ours |\n"
            "|---|---|---|---|---|---|---|---|")

    def __init__(self, bench):
        self.b = bench
        self.lines = []

    def t(self, key):
        r = self.b.get(key)
        return None if r is None else r["s"]

    def c(self, key, counter, default=None):
        r = self.b.get(key)
        return default if r is None or counter not in r else r[counter]

    def row(self, kernel, inp, one, two, peer_name, peer):
        """one/two: seconds (or None); peer: seconds against `one` (1 thread)."""
        self.lines.append(f"| {kernel} | {inp} | {fmt(one)} | {fmt(two) if two is not None else '—'} | "
                          f"{ratio(one, two) if two is not None else '—'} | {peer_name} | "
                          f"{fmt(peer) if peer is not None else '—'} | {ratio(peer, one)} |")

    def section(self, title):
        self.lines.append(f"| **{title}** | | | | | | | |")


def association_rows(T, folder):
    T.section("association of recorded track sets (default `associate`)")
    ss = [load_json(folder, f"stonesoup_recorded_sync_{r}.json") for r in (1, 2, 3)]
    ss_t = [s["stonesoup-one2one"]["assoc_time_s"] for s in ss if s and "stonesoup-one2one" in s]
    ss_med = statistics.median(ss_t) if ss_t else None
    ok = "; both 100 % correct" if ss and ss[0] and ss[0]["stonesoup-one2one"].get("correct_rate") == 1.0 else ""
    T.row("`associate` (lr+ls per component)", "`recorded_sync` (3 × 25, synchronous)",
          T.t("BM_DefaultAssociation/4/1"), T.t("BM_DefaultAssociation/4/2"),
          f"Stone Soup OneToOneTrackAssociator, P₁+P₂ (median of {len(ss_t)}{ok})", ss_med)
    T.row("`associate`", "`recorded_5s` (5 × 60, asynchronous)", T.t("BM_DefaultAssociation/1/1"),
          T.t("BM_DefaultAssociation/1/2"), "dense S-D tensor + lr+ls (`--sd`, naive)",
          T.t("BM_DenseSDAssociation/1"))
    T.row("`associate`", "`recorded_10k` (3 × 10 000)", T.t("BM_DefaultAssociation/3/1"),
          T.t("BM_DefaultAssociation/3/2"), "none runs at this size (dense: 10¹² entries); stages below", None)
    k = "BM_WideAreaStitching/threads:1"
    T.row("fragment stitching alone (`track_stitching.hpp`)",
          f"`widearea_small` ({T.c(k, 'groups', 0):.0f} groups, {T.c(k, 'candidates', 0):.0f} gated "
          f"continuations, {T.c(k, 'stitches', 0):.0f} joins)", T.t(k), T.t("BM_WideAreaStitching/threads:2"),
          "— (thread ratio; Stone Soup's `TrackStitcher` on the first 600 s: [status.md](status.md))", None)


def lap_rows(T, folder):
    T.section("2-D assignment (LAP)")
    scipy = {(r["kind"], r["n"]): r["median_ms"] * 1e-3 for r in (load_json(folder, "lap_scipy.json") or [])}
    for kind in ("uniform", "geometric"):
        for n in (100, 1000, 2000):
            T.row("JV with its initialisation (`lap.hpp`)", f"{kind} n = {n}", T.t(f"BM_Lap/{kind}/{n}"), None,
                  "scipy `linear_sum_assignment`", scipy.get((kind, n)))
    for kind in ("uniform", "geometric"):
        for n in (1000, 2000):
            T.row("JV with its initialisation", f"{kind} n = {n}", T.t(f"BM_Lap/{kind}/{n}"), None,
                  "plain shortest augmenting path (ours, naive)", T.t(f"BM_LapPlain/{kind}/{n}"))
    for kind in ("uniform", "geometric"):
        sc = scipy.get((kind, 1000))
        T.row("4 LAPs in parallel (`solve_lap_batch`)", f"{kind} n = 1000", T.t(f"BM_LapBatch4/{kind}/1000/1"),
              T.t(f"BM_LapBatch4/{kind}/1000/2"), "4 × scipy", None if sc is None else 4 * sc)
    for per_mille in (2, 10, 50, 100, 200):
        d = T.c(f"BM_GatedSparse/{per_mille}", "density")
        T.row("sparse LAP (`lap_sparse.hpp`)", f"gated geometric n = 1000, density "
              f"{'?' if d is None else f'{100 * d:.2g} %'}", T.t(f"BM_GatedSparse/{per_mille}"), None,
              "dense JV on the same gated matrix", T.t(f"BM_GatedDense/{per_mille}"))
    for n in (250, 1000, 2000):
        T.row("GNN tracker, 12 scans (grid gate, sparse LAP)", f"{n} targets",
              T.t(f"BM_GnnTracker/targets:{n}/sparse:1"), None, "the same with the dense LAP",
              T.t(f"BM_GnnTracker/targets:{n}/sparse:0"))


def exact_rows(T, folder):
    T.section("3-D assignment: exact and Lagrangian")
    cbc = {r["instance"]: r for r in (load_json(folder, "cbc_decomplib.json") or [])}
    for n in (5, 10, 20, 30, 40, 50):
        ours = [T.t(f"BM_ExactDecompLib/{n}/{r}") for r in range(1, 11)]
        proven = sum(1 for r in range(1, 11) if T.c(f"BM_ExactDecompLib/{n}/{r}", "optimal") == 1)
        peer = [cbc[f"ap3.{n}.{r}"] for r in range(1, 11) if f"ap3.{n}.{r}" in cbc]
        peer_t = [p["wall_s"] for p in peer]
        peer_ok = sum(1 for p in peer if p["matches_optimum"])
        per = [p["wall_s"] / o for p, o in zip(peer, ours) if o]
        mine = [o for o in ours if o is not None]
        inp = (f"DecompLib ap3.{n}.1–10: proven {proven}/10, CBC {peer_ok}/{len(peer)}; max ours "
               f"{fmt(max(mine)) if mine else '?'}, CBC {fmt(max(peer_t)) if peer_t else '?'}; "
               f"per instance CBC/ours ≥ {ratio(min(per), 1) if per else '?'}")
        T.row("exact branch and bound, median", inp, statistics.median(mine) if mine else None, None,
              "CBC 2.10, one thread, median", statistics.median(peer_t) if peer_t else None)
    bs = {}
    for r in load_json(folder, "cbc_balas_saltzman.json") or []:
        bs.setdefault(int(r["instance"].split(".")[1]), []).append(r)
    for n in (14, 18, 22, 26):
        ours = T.c(f"BM_ExactBalasSaltzman/{n}/1", "s_per_instance")
        ok = T.c(f"BM_ExactBalasSaltzman/{n}/1", "all_optimal") == 1
        peer = bs.get(n, [])
        T.row("exact branch and bound, per instance", f"Balas–Saltzman bs.{n}.1–5 ({'all proven' if ok else 'NOT all proven'}"
              f", CBC {sum(p['matches_optimum'] for p in peer)}/{len(peer)})", ours,
              T.c(f"BM_ExactBalasSaltzman/{n}/2", "s_per_instance"), "CBC, one thread, median",
              statistics.median(p["wall_s"] for p in peer) if peer else None)
    for n in (40, 50):
        ours = [T.t(f"BM_LagrangianDecompLib/{n}/{r}") for r in range(1, 11)]
        lp = [cbc.get(f"ap3.{n}.{r}", {}) for r in range(1, 11)]
        pairs = [(T.c(f"BM_LagrangianDecompLib/{n}/{r}", "lower_bound"), p.get("lp_bound"))
                 for r, p in zip(range(1, 11), lp)]
        pairs = [(ours_b, lp_b) for ours_b, lp_b in pairs if ours_b is not None and lp_b is not None]
        at_lp = sum(1 for ours_b, lp_b in pairs if ours_b >= math.ceil(lp_b - 1e-6))  # integer costs: ⌈LP⌉
        frac = [ours_b / lp_b for ours_b, lp_b in pairs]
        lp_t = [p["lp_s"] for p in lp if p.get("lp_s") is not None]
        mine = [o for o in ours if o is not None]
        T.row("Lagrangian relaxation (lr, 300 iterations or 0.1 %)", f"DecompLib ap3.{n}.1–10: its bound = ⌈LP bound⌉ on "
              f"{at_lp} of {len(pairs)} ({100 * min(frac):.1f}–{100 * max(frac):.1f} % of it)" if frac else f"DecompLib ap3.{n}.1–10",
              statistics.median(mine) if mine else None, None, "CBC's LP relaxation (CLP), median",
              statistics.median(lp_t) if lp_t else None)
    for n in (100, 200):
        gap = T.c(f"BM_LagrangianToOnePercent/lr/{n}/1", "gap_pct")
        T.row("Lagrangian relaxation to a 1 % gap", f"tracking tensor n = {n} (gap {gap:.2f} %)" if gap is not None
              else f"tracking tensor n = {n}", T.t(f"BM_LagrangianToOnePercent/lr/{n}/1"),
              T.t(f"BM_LagrangianToOnePercent/lr/{n}/2"), "— (thread ratio)", None)
    T.section("S-D assignment (S ≥ 3, seed 004's 25 dense targets)")
    for S in (4, 5):
        e = T.c(f"BM_SDProblem/{S}/1", "entries")
        T.row("S-D problem: statistics + dense tensor", f"S = {S} ({'?' if e is None else f'{e / 1e6:.3g} M'} entries)",
              T.t(f"BM_SDProblem/{S}/1"), T.t(f"BM_SDProblem/{S}/2"), "— (thread ratio)", None)
        gap = T.c(f"BM_SDLagrangian/{S}/1", "gap")
        T.row("S-D lr+ls to 0.1 %", f"S = {S} (gap {100 * gap:.2f} %)" if gap is not None else f"S = {S}",
              T.t(f"BM_SDLagrangian/{S}/1"), T.t(f"BM_SDLagrangian/{S}/2"),
              "seed 004's CHNN with pseudo-tracks, Eq. 12 gate" if S == 4 else "—",
              T.t("BM_ChnnPseudo/1/1") if S == 4 else None)
    T.row("seed 004 CHNN, Eq. 12 gate", f"S = 4 ({T.c('BM_ChnnPseudo/1/1', 'neurons', 0):.0f} neurons)",
          T.t("BM_ChnnPseudo/1/1"), T.t("BM_ChnnPseudo/1/2"),
          f"Eq. 7 only ({T.c('BM_ChnnPseudo/0/1', 'neurons', 0):.0f} neurons)", T.t("BM_ChnnPseudo/0/1"))


def kernel_rows(T, folder):
    T.section("sparse path (`associate --sparse`, 3 sensors, 100 targets per 100 km², seed 000 gate)")
    for n in (1000, 10000):
        T.row("candidates (grid index)", f"n = {n}", T.t(f"BM_SparseCandidates/n:{n}/threads:1"),
              T.t(f"BM_SparseCandidates/n:{n}/threads:2"), "all-pairs scan, same bound (naive)",
              T.t(f"BM_AllPairsCandidates/n:{n}/threads:1"))
    T.row("statistic on candidate pairs", "n = 1000", T.t("BM_SparseStatistic/n:1000/threads:1"),
          T.t("BM_SparseStatistic/n:1000/threads:2"), "dense all-pairs statistic (naive)",
          T.t("BM_DenseStatistic/n:1000/threads:1"))
    T.row("problem end to end (alignment … components)", "n = 10 000", T.t("BM_SparseProblem/n:10000/threads:1"),
          T.t("BM_SparseProblem/n:10000/threads:2"), "— (thread ratio; stages above)", None)
    T.row("problem with `--sparse`'s default options (calibrated gate)", f"n = 1000 "
          f"({T.c('BM_SparseProblemDefaults/n:1000/threads:1', 'candidates_12', 0) / 1e3:.0f} k candidate pairs 1–2)",
          T.t("BM_SparseProblemDefaults/n:1000/threads:1"), T.t("BM_SparseProblemDefaults/n:1000/threads:2"),
          "the same problem with the seed 000 gate (row above's options)", T.t("BM_SparseProblem/n:1000/threads:1"))
    T.row("the same options with seed 000's gate alone (its time-averaged index)",
          f"n = 1000 ({T.c('BM_SparseProblemDefaultsSeed000Gate/n:1000/threads:1', 'candidates_12', 0) / 1e3:.1f} k "
          "candidate pairs 1–2)",
          T.t("BM_SparseProblemDefaultsSeed000Gate/n:1000/threads:1"),
          T.t("BM_SparseProblemDefaultsSeed000Gate/n:1000/threads:2"),
          "the defaults (the row above)", T.t("BM_SparseProblemDefaults/n:1000/threads:1"))
    T.row("the same with the lag terms forced on these independent-error reports (before the whiteness test)",
          f"n = 1000 ({T.c('BM_SparseProblemDefaultsLagForced/n:1000/threads:1', 'candidates_12', 0) / 1e3:.0f} k "
          "candidate pairs 1–2)",
          T.t("BM_SparseProblemDefaultsLagForced/n:1000/threads:1"),
          T.t("BM_SparseProblemDefaultsLagForced/n:1000/threads:2"),
          "the defaults (the row above)", T.t("BM_SparseProblemDefaults/n:1000/threads:1"))
    T.row("problem with `--sparse`'s default options on filtered tracks",
          f"recorded_10k, 3 × 10 000 targets ({T.c('BM_RecordedProblem/defaults/threads:1', 'gated_12', 0) / 1e3:.1f} k "
          "gated pairs 1–2)",
          T.t("BM_RecordedProblem/defaults/threads:1"), T.t("BM_RecordedProblem/defaults/threads:2"),
          f"the same file with seed 000's options ({T.c('BM_RecordedProblem/seed000/threads:1', 'gated_12', 0) / 1e3:.1f} k gated)",
          T.t("BM_RecordedProblem/seed000/threads:1"))
    T.row("components solved", "n = 10 000", T.t("BM_SparseSolve/n:10000/threads:1"),
          T.t("BM_SparseSolve/n:10000/threads:2"), "— (thread ratio)", None)
    T.section("dense kernels")
    for form in ("Chain", "AllPairs"):
        T.row(f"cost tensor, {form.lower()} form", "n = 200 (8 M entries)",
              T.t(f"BM_CostTensor{form}/n:200/threads:1"), T.t(f"BM_CostTensor{form}/n:200/threads:2"),
              "STREAM-style write of the same tensor (floor)", T.t("BM_StreamWrite/n:200/threads:1"))
    T.row("cost tensor, chain form", "n = 200", T.t("BM_CostTensorChain/n:200/threads:1"), None,
          "naive triple loop", T.t("BM_CostTensorChainNaive/n:200/threads:1"))
    for n in (100000, 1000000):
        T.row("CV Kalman bank, predict + update (SoA)", f"{n} 2-D tracks", T.t(f"BM_CvBank/tracks:{n}/threads:1"),
              T.t(f"BM_CvBank/tracks:{n}/threads:2"), "per-track fixed-size Eigen loop",
              T.t(f"BM_EigenPerTrack/tracks:{n}/threads:1"))
    T.row("IMM bank (CV/CA/CS)", "100 000 tracks", T.t("BM_ImmBank/tracks:100000/threads:1"),
          T.t("BM_ImmBank/tracks:100000/threads:2"), "— (thread ratio)", None)
    T.row("alpha-beta bank", "2²⁰ tracks", T.t("BM_AlphaBetaBank/1048576/1"), T.t("BM_AlphaBetaBank/1048576/2"),
          "per-track calls (naive)", T.t("BM_AlphaBetaPerTrack/1048576"))
    T.section("Hopfield networks (seed 000, 004)")
    for n in (100, 200):
        floor_ms = T.c(f"BM_SyncSweep/{n}/1", "floor_ms")
        T.row("synchronous sweep", f"n = {n} ({n ** 3:,} neurons)", T.t(f"BM_SyncSweep/{n}/1"),
              T.t(f"BM_SyncSweep/{n}/2"), "memory floor (12 B/neuron at the copy bandwidth)",
              None if floor_ms is None else floor_ms * 1e-3)
    T.row("sweep from marginal sums", "n = 15", T.t("BM_MarginalSweepSmall/15"), None,
          "the n⁶-weight network (naive)", T.t("BM_NaiveWeightsSweep/15"))
    T.row("restarts, default solver", "n = 50", T.t("BM_RestartsDefault/1"), T.t("BM_RestartsDefault/2"),
          "— (thread ratio)", None)
    T.row("continuous step (CHNN)", "n = 100", T.t("BM_ContinuousSyncStep/100/1"),
          T.t("BM_ContinuousSyncStep/100/2"), "— (thread ratio)", None)
    T.section("seed 001, seed 003, io")
    for J in (100, 1000):
        T.row("fuzzy association, per packet", f"{J} system tracks", T.t(f"BM_FuzzyAssociation/{J}"), None,
              "FTAA (the paper's baseline)", T.t(f"BM_Ftaa/{J}"))
    T.row("Siamese scoring at density 80, embed once", "64 pairs", T.t("BM_SiameseScoreEmbedOnce/1"),
          T.t("BM_SiameseScoreEmbedOnce/2"), "both branches per pair (the paper's way)",
          T.t("BM_SiameseScorePerPair/1"))
    T.row("Siamese training step", "batch", T.t("BM_SiameseTrainingStep/1"), T.t("BM_SiameseTrainingStep/2"),
          "— (thread ratio)", None)
    npy = load_json(folder, "csv_numpy.json")
    T.row("`import csv` parse + tracks", "10⁶ rows, 52 MB", T.t("BM_ImportCsv/0"), None,
          f"{npy['peer']} (numbers only)" if npy else "numpy loadtxt", npy["median_s"] if npy else None)


COMMANDS = """Reproduce: `scripts/bench.sh` (about an hour; writes `bench-results/`, then this table as
`bench-results/report.md`). Each row's source, for a single re-run:
- association: `build/bench_recorded`, stitching: `build/bench_widearea`; Stone Soup: `/usr/bin/python3 bench/stonesoup_t2t.py FILE --cov sum`
  on `build/trackassoc simulate --scenario recorded_sync --seed 1 -o FILE`;
- LAP: `build/bench_lap`, `build/bench_lap_sparse`, `build/bench_gnn_tracker`; scipy: `bench/lap_scipy.py`;
- exact, LR: `build/bench_3d_solvers`; CBC and its LP: `bench/cbc_3d.py --set decomplib|balas-saltzman`;
- S-D: `build/bench_sd`; sparse path: `build/bench_sparse`; tensor: `build/bench_cost_tensor`;
- filters: `build/bench_filters`, `build/bench_fuzzy`; Hopfield: `build/bench_hopfield`;
  Siamese: `build/bench_siamese`; CSV: `build/bench_csv_import` and `bench/csv_numpy.py`.
All with `--benchmark_repetitions=5 --benchmark_report_aggregates_only=true`; times are wall-clock
medians; "peer / ours" > 1 means ours is faster."""


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "bench-results"
    T = Table(load_benchmarks(folder))
    for part in (association_rows, lap_rows, exact_rows, kernel_rows):
        part(T, folder)
    meta = os.path.join(folder, "meta.txt")
    if os.path.exists(meta):
        with open(meta) as f:
            print("Run: " + "; ".join(line.strip() for line in f if line.strip()) + "\n")
    print(Table.HEAD)
    print("\n".join(T.lines))
    print()
    print(COMMANDS)
    return 0


if __name__ == "__main__":
    sys.exit(main())
