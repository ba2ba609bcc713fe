#!/usr/bin/env bash
# The fuzz stage of CI (docs/reliability.md): builds the libFuzzer targets tests/fuzz/fuzz_*.cpp
# with clang into build-fuzz/ (only they and the readers they link) and runs each for
# FUZZ_SECONDS (default 45) from a copy of its committed seed corpus tests/fuzz/corpus/<target>/.
# A crash, a sanitizer report, an input running over 10 s or a run over 2 GB fails the script; the
# input that did it is kept in build-fuzz/artifacts/<target>/ (make it a regression test:
# tests/fuzz/regressions/ and a gtest that reads it and expects a clean error).
# Usage: scripts/fuzz.sh [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (CMakeLists.txt uses it when present): paths relative to the checkout and no compile
# folder in the hash, so a clone in another folder reuses the objects of an earlier build.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}" CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"

seconds=${FUZZ_SECONDS:-45}
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for src in tests/fuzz/fuzz_*.cpp; do targets+=("$(basename "$src" .cpp)"); done
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
build_start=$(date +%s)
CC=clang CXX=clang++ cmake -S . -B build-fuzz "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DTRACKASSOC_BUILD_FUZZ=ON -DTRACKASSOC_BUILD_TESTS=OFF -DTRACKASSOC_BUILD_BENCH=OFF \
  -DTRACKASSOC_NATIVE=OFF >/dev/null
cmake --build build-fuzz --target "${targets[@]}" -j "$(nproc)" >build-fuzz/build.log 2>&1 || {
  tail -40 build-fuzz/build.log
  echo "fuzz: build FAILED"
  exit 1
}
echo "fuzz: built ${targets[*]} in $(($(date +%s) - build_start)) s"

status=0
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t artifacts=build-fuzz/artifacts/$t log=build-fuzz/$t.log
  rm -rf "$work" "$artifacts"
  mkdir -p "$work" "$artifacts"
  cp tests/fuzz/corpus/"$t"/* "$work"/
  start=$(date +%s)
  if build-fuzz/"$t" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$artifacts"/ "$work" >"$log" 2>&1; then
    result=ok
  else
    result=FAILED
    status=1
  fi
  runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo "?")
  echo "fuzz: $t $result: $runs inputs in $(($(date +%s) - start)) s, corpus $(ls "$work" | wc -l) files"
  if [ "$result" = FAILED ]; then
    grep -E "ERROR|SUMMARY|Test unit written|deadly signal|timeout" "$log" | head -20 || true
    tail -30 "$log"
  fi
done
exit $status
