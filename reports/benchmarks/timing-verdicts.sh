#!/usr/bin/env bash
# Issue 20's timing-verdict study on this machine (a command of its own, not
# a test): how often an unchanged tree is flagged, quiet and under a
# concurrent build, and how reliably a real slowdown of one pass is found.
#
#   reports/benchmarks/timing-verdicts.sh [--suite DIR] [--nights N] [--loaded K]
#                                         [--factors "1.2 1.3 1.5"] [--out DIR]
#
# 1. A baseline of the suite (nightly --update-baseline into a scratch root).
# 2. N nightlies of the unchanged tree against it; the last K of them with a
#    build of this project (-j nproc, a scratch build folder) running beside.
# 3. For each factor, N nightlies with GIHARNESS_TEST_SLOW_PASS=light_tiles:F
#    (gpu/compute_pass.cpp: the pass really does F times its work; light_tiles
#    only writes what it reads from elsewhere, so its bits are unchanged).
# Prints one line per night and a table; writes <out>/timing-verdicts.json.
# Default suite: the default suite's realtime DI scenarios (they all run
# light_tiles); pass --suite scenarios for every scenario.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin="$root/build/giharness"
out=/tmp/giharness-timing-study
nights=10
loaded=5
factors="1.2 1.3 1.5"
suite=""
while [ $# -gt 0 ]; do
  case "$1" in
    --suite) suite=$2; shift 2 ;;
    --nights) nights=$2; shift 2 ;;
    --loaded) loaded=$2; shift 2 ;;
    --factors) factors=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "timing-verdicts.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -x "$bin" ] || { echo "timing-verdicts.sh: build first (.ci/build)" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out"
if [ -z "$suite" ]; then
  suite="$out/suite"
  mkdir -p "$suite"
  cp "$root"/scenarios/di_*.json "$suite"/
  cp "$root"/scenarios/schema.json "$suite"/ 2>/dev/null || true
fi
baselines="$out/baselines"

load_pid=""
start_load() {
  rm -rf "$out/load-build"
  cmake -S "$root" -B "$out/load-build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  (cmake --build "$out/load-build" -j "$(nproc)" >/dev/null 2>&1 || true) &
  load_pid=$!
  sleep 20  # past configure, into the compilers
}
stop_load() {
  if [ -n "$load_pid" ]; then
    pkill -P "$load_pid" 2>/dev/null || true
    kill "$load_pid" 2>/dev/null || true
    pkill -f "$out/load-build" 2>/dev/null || true
    wait "$load_pid" 2>/dev/null || true
    load_pid=""
  fi
}
trap stop_load EXIT

# One night: prints "<label> exit <code> regressed <scenarios> <series...>".
night() {
  local label=$1 env=$2 dir="$out/nights/$1"
  local t0=$SECONDS code=0
  env $env "$bin" nightly --suite "$suite" --out "$dir" --baseline "$baselines" >"$dir.log" 2>&1 || code=$?
  python3 - "$dir/summary.json" "$label" "$code" "$((SECONDS - t0))" <<'EOF' | tee -a "$out/nights.txt"
import json, sys
s = json.load(open(sys.argv[1]))
flagged, tiles = [], []
for row in s["scenarios"]:
    for t in row.get("timing", {}).get("series", []):
        if t["verdict"] == "regressed":
            flagged.append(f'{row["name"]}/{t["name"]}')
        if t["name"] == "light_tiles":
            tiles.append(t["ratio"])
tiles.sort()
med = tiles[len(tiles) // 2] if tiles else float("nan")
print(json.dumps({"night": sys.argv[2], "exit": int(sys.argv[3]), "seconds": int(sys.argv[4]),
                  "verdict": s["verdict"], "flagged": flagged, "light_tiles_ratio_median": med,
                  "series_compared": sum(len(r.get("timing", {}).get("series", [])) for r in s["scenarios"])}))
EOF
}

mkdir -p "$out/nights"
echo "baseline of $suite ..."
"$bin" nightly --suite "$suite" --out "$out/baseline-run" --baseline "$baselines" --update-baseline >"$out/baseline-run.log" 2>&1
for i in $(seq 1 "$nights"); do
  if [ "$i" -gt $((nights - loaded)) ]; then start_load; night "unchanged-loaded-$i" ""; stop_load
  else night "unchanged-quiet-$i" ""; fi
done
for f in $factors; do
  for i in $(seq 1 "$nights"); do night "slow-$f-$i" "GIHARNESS_TEST_SLOW_PASS=light_tiles:$f"; done
done

python3 - "$out" <<'EOF'
import json, sys, collections
out = sys.argv[1]
rows = [json.loads(l) for l in open(f"{out}/nights.txt")]
groups = collections.OrderedDict()
for r in rows:
    key = r["night"].rsplit("-", 1)[0]
    groups.setdefault(key, []).append(r)
table = []
print(f'{"nights":24} {"runs":>4} {"flagged runs":>12} {"light_tiles flagged":>19} {"other flags":>11} {"light_tiles ratio (median)":>27}')
for key, rs in groups.items():
    tiles = sum(any(f.endswith("/light_tiles") for f in r["flagged"]) for r in rs)
    other = sum(sum(not f.endswith("/light_tiles") and not f.endswith("/pipeline_total") for f in r["flagged"]) for r in rs)
    ratios = sorted(r["light_tiles_ratio_median"] for r in rs)
    line = {"nights": key, "runs": len(rs), "flagged_runs": sum(bool(r["flagged"]) for r in rs),
            "light_tiles_flagged_runs": tiles, "other_series_flagged": other,
            "light_tiles_ratio_median": ratios[len(ratios) // 2], "seconds_per_night": sum(r["seconds"] for r in rs) / len(rs)}
    table.append(line)
    print(f'{key:24} {len(rs):4} {line["flagged_runs"]:12} {tiles:19} {other:11} {line["light_tiles_ratio_median"]:27.3f}')
json.dump({"nights": rows, "table": table}, open(f"{out}/timing-verdicts.json", "w"), indent=1)
EOF
echo "record: $out/timing-verdicts.json"
