#!/bin/bash
# The independent recordings of docs/status.md ("Independent recordings"): track files made by
# Stone Soup's own models and trackers (bench/stonesoup_recordings.py), never by trackassoc's
# simulator, scored with `associate` (no flag) and `evaluate`; with --peer also Stone Soup's
# track-to-track associators on the same files (bench/stonesoup_t2t.py, resampled onto a common
# grid as a user would).
#
#   bash scripts/independent_recordings.sh [OUT_DIR] [SEEDS] [--peer]
#
# OUT_DIR defaults to build/independent, SEEDS to 4 (6 kinds × SEEDS files, ~10 s each to make on
# one core). Needs build/trackassoc (scripts/build.sh), Debian's /usr/bin/python3 with numpy and
# h5py, and the Python packages of ../shared/peers/stonesoup-src/README.md. Prints one line per kind:
# targets, correct %, false tuples, coexisting cross-radar pairs linked, pair precision.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/independent}
seeds=${2:-4}
peer=${3:-}
bin=build/trackassoc
gen=bench/stonesoup_recordings.py
[ -x "$bin" ] || { echo "independent_recordings: $bin not built (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out/files" "$out/associated"

kinds() {  # kind and generator arguments, one per line
  echo "clean"
  echo "bias --range-bias 60,-120,190 --azimuth-bias 0.3,-0.6,0.6"
  echo "site --site-error 0,530,0"
  echo "clock --clock-offset 0,0,1.5"
  echo "recycled --recycle 30"
  echo "airway --airway --targets 40 --box 12000 --range-bias 60,-120,190 --azimuth-bias 0.3,-0.6,0.6"
}

for seed in $(seq 1 "$seeds"); do
  kinds | while read -r kind args; do
    f="$out/files/${kind}_$seed.h5"
    [ -s "$f" ] || echo "/usr/bin/python3 $gen $f --seed $seed $args"
  done
done | xargs -P "$(nproc)" -I{} sh -c '{}'

for f in "$out"/files/*.h5; do
  name=$(basename "$f" .h5)
  "$bin" associate -i "$f" -o "$out/associated/$name.h5" > "$out/associated/$name.log"
  "$bin" evaluate -i "$out/associated/$name.h5" > "$out/associated/$name.eval"
  if [ "$peer" = "--peer" ]; then
    /usr/bin/python3 bench/stonesoup_t2t.py "$f" --cov sum --json "$out/associated/$name.stonesoup.json" \
      > "$out/associated/$name.stonesoup.log"
  fi
done

/usr/bin/python3 - "$out/associated" <<'PY'
import collections, glob, json, os, re, sys
d = sys.argv[1]
ours = collections.defaultdict(lambda: [0, 0.0, 0, 0, 0, 0, 0, 0])
peer = collections.defaultdict(lambda: collections.defaultdict(lambda: [0, 0.0, 0]))
for e in sorted(glob.glob(d + "/*.eval")):
    kind = os.path.basename(e).rsplit("_", 1)[0]
    lines = open(e).read().split("\n")
    a = lines[2].replace("%", "").split()
    g = ours[kind]
    g[0] += int(a[1]); g[1] += int(a[1]) * float(a[2]) / 100; g[2] += int(a[5]); g[3] += int(a[7])
    pairs = re.findall(r"\((\d+) of (\d+)\)", lines[6])
    g[4] += int(pairs[0][0]); g[5] += int(pairs[0][1]); g[6] += int(pairs[-1][0]); g[7] += int(pairs[-1][1])
    j = e[:-5] + ".stonesoup.json"
    if os.path.exists(j):
        for method, r in json.load(open(j)).items():
            p = peer[kind][method]
            p[0] += r["targets"]; p[1] += r["targets"] * r["correct_rate"]; p[2] += r["false_tuples"]
for kind, g in ours.items():
    print(f"{kind:9s} targets {g[0]:4d}  correct {100 * g[1] / g[0]:5.1f} %  false tuples {g[2]:3d} of {g[3]:4d}"
          f"  coexisting pairs {100 * g[4] / max(g[5], 1):5.1f} %  pair precision {100 * g[6] / max(g[7], 1):6.2f} %")
    for method, p in sorted(peer[kind].items()):
        print(f"          {method:29s} correct {100 * p[1] / max(p[0], 1):5.1f} %  false tuples {p[2]}")
PY
