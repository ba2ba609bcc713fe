#!/usr/bin/env bash
# One MPI test case (issue 19 item 5; registered by CMakeLists.txt in the MPI build only, run by
# scripts/test_mpi.sh): `mpirun -np 2 --oversubscribe` against one process on small files, the
# datasets compared byte for byte (tests/mpi/compare_h5.py; wall times by shape only).
# Usage: mpi_case.sh CASE TRACKASSOC_BINARY
set -uo pipefail
case_name=$1
bin=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/trackassoc-mpi-XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"
mpirun_args=(--oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun_args+=(--allow-run-as-root)
mpi() { local n=$1; shift; mpirun -q "${mpirun_args[@]}" -np "$n" "$@"; }
compare() { /usr/bin/python3 "$here/compare_h5.py" "$@"; }
fail() { echo "FAIL: $*"; exit 1; }
# The line count of trackassoc's own errors (mpirun may add its own report of the exit status).
error_lines() { grep -c '^trackassoc: \(internal \)\?error:' "$1"; }
# A sharded study against one process: `ARGS -o one.h5` against 2 and 3 ranks and 2 ranks x 2
# threads, the same datasets (but IGNORE, the wall times) and the table printed once, by rank 0
# (ONCE: a pattern of its closing line); one.txt, np2.txt, np3.txt keep what was printed.
# Usage: against_one IGNORE ONCE ARGS...
against_one() {
  local ignore=$1 once=$2
  shift 2
  "$bin" "$@" -o one.h5 > one.txt || fail "one process"
  for n in 2 3; do
    mpi "$n" "$bin" "$@" -o "np$n.h5" > "np$n.txt" || fail "$n ranks"
    compare one.h5 "np$n.h5" --ignore "$ignore" || fail "$n ranks differ"
    [ "$(grep -c "$once" "np$n.txt")" -eq 1 ] || fail "$n ranks: the table is printed once, by rank 0"
  done
  mpi 2 "$bin" "$@" --threads 2 -o t2.h5 > /dev/null || fail "2 ranks, 2 threads"
  compare one.h5 t2.h5 --ignore "$ignore" || fail "2 ranks x 2 threads differ"
}

case "$case_name" in
  seed000)  # sharded Monte Carlo: 1 vs 2 and 3 ranks, and 2 ranks x 2 threads
    against_one wall_time_s wrote experiment seed000 --targets 5 --runs 3 --solvers lr hopfield --no-plots --seed 7
    # The table's rates (every column but the times) are those of one process.
    diff <(grep -v '^wrote' one.txt | sed 's/ *[0-9.]*$//') <(grep -v '^wrote' np2.txt | sed 's/ *[0-9.]*$//') \
      || fail "the tables differ"
    ;;
  seed004)
    args=(experiment seed004 --runs 2 --solvers lr+ls chnn-eq12 --no-plots)
    "$bin" "${args[@]}" -o one.h5 > /dev/null || fail "one process"
    mpi 2 "$bin" "${args[@]}" -o np2.h5 > /dev/null || fail "2 ranks"
    compare one.h5 np2.h5 --ignore wall_time_s || fail "2 ranks differ"
    ;;
  seed001)  # both readings' runs sharded (and in parallel within a rank)
    against_one time_per_association_s '^wall time' experiment seed001 --runs 4 --duration 60 --no-plots --seed 5
    # The tables but the times: the time/assoc column (8th field of a row) and the wall time line.
    strip() { grep -v '^wall time' "$1" | awk '/^(erratum|literal) /{$8=""} {print}'; }
    diff <(strip one.txt) <(strip np2.txt) || fail "the tables differ"
    ;;
  seed002)  # the table's and the sweep's motions sharded
    against_one wall_time_s '^wrote' experiment seed002 --runs 6 --sensitivity --sensitivity-ca-sigma 1 5 \
      --sensitivity-a-max 100 --no-plots --seed 5
    # Every line but the two wall times "(1.23 s)" and "runs, 0.12 s)", and the file name.
    strip() { grep -v '^wrote' "$1" | sed -E 's/[0-9.]+ s\)/s)/'; }
    for n in 2 3; do diff <(strip one.txt) <(strip "np$n.txt") || fail "$n ranks: the tables differ"; done
    ;;
  seed003)  # the scenes sharded, the models read on every rank
    against_one seconds '^results ->' experiment seed003 --runs 3 --densities 5 10
    # Every table but the time table, and not the closing line's wall time.
    strip() { grep -v '^results ->' "$1" | awk '/^time \[ms\]/{skip=1} /^$/{skip=0} !skip'; }
    diff <(strip one.txt) <(strip np3.txt) || fail "the tables differ"
    ;;
  schedules)  # the instances sharded (tracking and DecompLib)
    against_one wall_time_s '^wrote' experiment schedules --sizes 5 --runs 3 --decomplib-sizes 10 \
      --decomplib-per-size 1 --restarts 2 --no-plots
    ;;
  associate)  # sharded components: 1 vs 2 and 3 ranks, 5 sensors and a dense case
    for sc in recorded_5s recorded_dense; do
      "$bin" simulate --scenario "$sc" --seed 3 -o "$sc.h5" > /dev/null || fail "simulate $sc"
      "$bin" associate -i "$sc.h5" -o "$sc-one.h5" > /dev/null || fail "one process $sc"
      for n in 2 3; do
        mpi "$n" "$bin" associate -i "$sc.h5" -o "$sc-np$n.h5" > "$sc-np$n.txt" || fail "$n ranks $sc"
        compare "$sc-one.h5" "$sc-np$n.h5" || fail "$sc: $n ranks differ"
        [ "$(grep -c '^associated' "$sc-np$n.txt")" -eq 1 ] || fail "printed once, by rank 0"
      done
    done
    # Registration errors: the registration stage re-associates on the corrected reports, every
    # round's components sharded; the same output as one process, /registration included.
    "$bin" simulate --scenario recorded_bias --seed 3 -o bias.h5 > /dev/null || fail "simulate recorded_bias"
    "$bin" associate -i bias.h5 -o bias-one.h5 > bias-one.txt || fail "one process recorded_bias"
    grep -q 'applied, [2-9][0-9]* associations' bias-one.txt || { cat bias-one.txt; fail "recorded_bias: registration not applied"; }
    for n in 2 3; do
      mpi "$n" "$bin" associate -i bias.h5 -o "bias-np$n.h5" > "bias-np$n.txt" || fail "$n ranks recorded_bias"
      compare bias-one.h5 "bias-np$n.h5" || fail "recorded_bias: $n ranks differ"
    done
    mpi 2 "$bin" associate -i recorded_5s.h5 -o exact-np2.h5 --solver exact --threads 2 > /dev/null || fail "exact"
    "$bin" associate -i recorded_5s.h5 -o exact-one.h5 --solver exact > /dev/null || fail "exact one"
    compare exact-one.h5 exact-np2.h5 || fail "exact: 2 ranks differ"
    ;;
  associate-widearea)  # a radar network (16 sensors): the build's gated statistics and the components sharded
    "$bin" simulate --scenario widearea_small --seed 2 -o wa.h5 > /dev/null || fail "simulate widearea_small"
    "$bin" associate -i wa.h5 -o wa-one.h5 --threads 1 > /dev/null || fail "one process widearea_small"
    for n in 2 3; do
      TRACKASSOC_MPI_STATS=1 mpi "$n" -x TRACKASSOC_MPI_STATS "$bin" associate -i wa.h5 -o "wa-np$n.h5" --threads 1 \
        > "wa-np$n.txt" 2> "wa-np$n.err" || { cat "wa-np$n.err"; fail "$n ranks widearea_small"; }
      compare wa-one.h5 "wa-np$n.h5" || fail "widearea_small: $n ranks differ"
      # The sensor pairs were dealt to every rank (items per rank: none at 0).
      grep 'gated statistics of the sensor pairs' "wa-np$n.err" | grep -q 'items (share of cost): [1-9]' \
        || { cat "wa-np$n.err"; fail "widearea_small: the statistics were not shared out"; }
      ! grep 'gated statistics of the sensor pairs' "wa-np$n.err" | grep -q ' 0 (0' \
        || { cat "wa-np$n.err"; fail "widearea_small: a rank got no sensor pair"; }
    done
    ;;
  associate-sparse)  # --sparse (three sensors) components sharded: 1 vs 2 and 3 ranks, lr and exact
    for sc in recorded_3s recorded_formation; do
      "$bin" simulate --scenario "$sc" --seed 3 -o "$sc.h5" > /dev/null || fail "simulate $sc"
      for s in lr exact; do
        "$bin" associate --sparse --solver "$s" -i "$sc.h5" -o "$sc-$s-one.h5" > /dev/null || fail "one process $sc $s"
        for n in 2 3; do
          mpi "$n" "$bin" associate --sparse --solver "$s" -i "$sc.h5" -o "$sc-$s-np$n.h5" > "$sc-$s-np$n.txt" \
            || fail "$n ranks $sc $s"
          compare "$sc-$s-one.h5" "$sc-$s-np$n.h5" || fail "$sc $s: $n ranks differ"
          [ "$(grep -c '^associated' "$sc-$s-np$n.txt")" -eq 1 ] || fail "printed once, by rank 0"
        done
      done
    done
    args=(associate --sparse --solver lr --cost-form chain -i recorded_formation.h5)
    "$bin" "${args[@]}" -o chain-one.h5 > /dev/null || fail "chain one"
    mpi 2 "$bin" "${args[@]}" --threads 2 -o chain-np2.h5 > /dev/null || fail "chain 2 ranks"
    compare chain-one.h5 chain-np2.h5 || fail "chain: 2 ranks differ"
    ;;
  rank-fails)  # a rank that fails names its shard; non-zero exit; no output, no .tmp
    "$bin" simulate --scenario recorded_3s -o in.h5 > /dev/null || fail "simulate"
    TRACKASSOC_FAULT_RANK=1 mpi 2 -x TRACKASSOC_FAULT_RANK "$bin" experiment seed000 --targets 5 --runs 2 \
      --solvers lr --no-plots -o study.h5 > out.txt 2> err.txt
    rc=$?
    [ "$rc" -ne 0 ] || fail "exit 0 after a failed rank"
    grep -q '^trackassoc: internal error: rank 1, seed000 run 1 of 5 targets' err.txt || { cat err.txt; fail "message"; }
    [ "$(error_lines err.txt)" -eq 1 ] || { cat err.txt; fail "one line"; }
    [ ! -e study.h5 ] && [ ! -e study.h5.tmp ] || fail "partial output left"
    # The default path shards its sensor pairs first (their statistics), so that round fails.
    TRACKASSOC_FAULT_RANK=1 mpi 2 -x TRACKASSOC_FAULT_RANK "$bin" associate -i in.h5 -o a.h5 > out.txt 2> err.txt
    [ $? -ne 0 ] || fail "associate: exit 0 after a failed rank"
    grep -q '^trackassoc: internal error: rank 1, [0-9]* sensor pairs ([0-9]* candidate pairs): fault injected' err.txt || { cat err.txt; fail "associate message"; }
    [ ! -e a.h5 ] && [ ! -e a.h5.tmp ] || fail "associate: partial output left"
    TRACKASSOC_FAULT_RANK=0 mpi 2 -x TRACKASSOC_FAULT_RANK "$bin" associate -i in.h5 -o a.h5 > out.txt 2> err.txt
    [ $? -ne 0 ] || fail "associate: exit 0 after rank 0 failed its share"
    grep -q '^trackassoc: internal error: rank 0, [0-9]* sensor pairs' err.txt || { cat err.txt; fail "rank 0 message"; }
    [ ! -e a.h5 ] || fail "rank 0 failure: output left"
    TRACKASSOC_FAULT_RANK=1 mpi 2 -x TRACKASSOC_FAULT_RANK "$bin" associate --sparse --solver lr -i in.h5 -o a.h5 \
      > out.txt 2> err.txt
    [ $? -ne 0 ] || fail "associate --sparse: exit 0 after a failed rank"
    grep -q '^trackassoc: internal error: rank 1, [0-9]* components ([0-9]* tracks): fault injected' err.txt \
      || { cat err.txt; fail "associate --sparse message"; }
    [ "$(error_lines err.txt)" -eq 1 ] || { cat err.txt; fail "associate --sparse: one line"; }
    [ ! -e a.h5 ] && [ ! -e a.h5.tmp ] || fail "associate --sparse: partial output left"
    ;;
  bad-input)  # bad input on rank 0: exit 2 with one line, the other ranks released
    echo "not hdf5" > bad.h5
    mpi 2 "$bin" associate -i bad.h5 -o a.h5 > out.txt 2> err.txt
    rc=$?
    [ "$rc" -eq 2 ] || { cat err.txt; fail "exit $rc, expected 2"; }
    [ "$(error_lines err.txt)" -eq 1 ] || { cat err.txt; fail "one line"; }
    grep -q '^trackassoc: error: .*bad.h5' err.txt || { cat err.txt; fail "names the file"; }
    [ ! -e a.h5 ] || fail "output left"
    mpi 2 "$bin" experiment seed000 --runs 0 -o s.h5 > out.txt 2> err.txt
    [ $? -eq 2 ] && [ "$(grep -c 'runs' err.txt)" -eq 1 ] || { cat err.txt; fail "usage error once"; }
    mpi 2 "$bin" experiment seed000 --runs 2 --targets 5 --no-plots -o nofolder/s.h5 > out.txt 2> err.txt
    [ $? -eq 2 ] && [ "$(error_lines err.txt)" -eq 1 ] || { cat err.txt; fail "output folder: exit 2, one line"; }
    ;;
  refused)  # commands and studies that do not shard refuse more than one rank, clearly
    mpi 2 "$bin" simulate --scenario recorded_3s -o s.h5 > out.txt 2> err.txt
    [ $? -eq 2 ] && grep -q 'simulate: runs as one process' err.txt || { cat err.txt; fail "simulate"; }
    mpi 2 "$bin" experiment recorded -o s.h5 > out.txt 2> err.txt
    [ $? -eq 2 ] && grep -q 'experiment recorded: runs as one process' err.txt || { cat err.txt; fail "recorded"; }
    grep -q 'experiment seed001`, `experiment seed002`, `experiment seed003`' err.txt || { cat err.txt; fail "names"; }
    "$bin" simulate --scenario recorded_3s -o in.h5 > /dev/null || fail "simulate"
    mpi 2 "$bin" associate -i in.h5 -o a.h5 --solver lr --3d > out.txt 2> err.txt
    [ $? -eq 2 ] && [ "$(error_lines err.txt)" -eq 1 ] && grep -q 'only the default pipeline' err.txt \
      || { cat err.txt; fail "--3d"; }
    mpi 2 "$bin" associate -i in.h5 -o a.h5 --sd > out.txt 2> err.txt
    [ $? -eq 2 ] && grep -q 'only the default pipeline' err.txt || { cat err.txt; fail "--sd"; }
    [ ! -e s.h5 ] && [ ! -e a.h5 ] || fail "output written"
    ;;
  *) fail "unknown case $case_name" ;;
esac
echo "PASS: $case_name"
