#!/usr/bin/env bash
# Issue 20's timing-verdict study on this machine (a command of its own, not
# a test): how often an unchanged tree is flagged, quiet and under a
# concurrent build, and how reliably a real slowdown of one pass is found.
#
#   reports/benchmarks/timing-verdicts.sh [--suite DIR] [--nights N] [--loaded K]
#                                         [--factors "1.2 1.3 1.5"] [--baseline-runs R] [--out DIR]
#
# 1. A baseline of the suite (nightly --update-baseline into a scratch root),
#    and R - 1 more runs of it added with --add-timing-run (default R = 3):
#    the baseline's run-to-run spread.
# 2. N nightlies of the unchanged tree against it; the last K of them with a
#    build of this project (-j nproc, a scratch build folder) running beside.
# 3. For each factor, N nightlies with GIHARNESS_TEST_SLOW_PASS=light_tiles:F
#    (gpu/compute_pass.cpp: the pass really does F times its work; light_tiles
#    only writes what it reads from elsewhere, so its bits are unchanged).
# Prints one line per night and a table (runs flagged, light_tiles named,
# scenarios not judged because the machine was loaded, the median share of
# CPU time the frames waited for a CPU); writes <out>/timing-verdicts.json.
# Default suite: the default suite's realtime DI scenarios (they all run
# light_tiles); pass --suite scenarios for every scenario.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin="$root/build/giharness"
out=/tmp/giharness-timing-study
nights=10
loaded=5
factors="1.2 1.3 1.5"
baseline_runs=3
suite=""
while [ $# -gt 0 ]; do
  case "$1" in
    --suite) suite=$2; shift 2 ;;
    --nights) nights=$2; shift 2 ;;
    --loaded) loaded=$2; shift 2 ;;
    --factors) factors=$2; shift 2 ;;
    --baseline-runs) baseline_runs=$2; shift 2 ;;
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
flagged, tiles, shares = [], [], []
loaded = 0
for row in s["scenarios"]:
    timing = row.get("timing", {})
    run_load = timing.get("load", {}).get("run")
    if run_load:
        shares.append(run_load["median_wait_share"])
    loaded += any(t["verdict"] == "loaded" for t in timing.get("series", []))
    for t in timing.get("series", []):
        if t["verdict"] == "regressed":
            flagged.append(f'{row["name"]}/{t["name"]}')
        if t["name"] == "light_tiles":
            tiles.append(t["ratio"])
tiles = sorted(t for t in tiles if t > 0)  # a series not judged has no ratio
med = tiles[len(tiles) // 2] if tiles else None
shares.sort()
print(json.dumps({"night": sys.argv[2], "exit": int(sys.argv[3]), "seconds": int(sys.argv[4]),
                  "verdict": s["verdict"], "flagged": flagged, "light_tiles_ratio_median": med,
                  "scenarios": len(s["scenarios"]), "scenarios_not_judged_loaded": loaded,
                  "wait_share_median": shares[len(shares) // 2] if shares else None,
                  "series_compared": sum(len(r.get("timing", {}).get("series", [])) for r in s["scenarios"])}))
EOF
}

mkdir -p "$out/nights"
echo "baseline of $suite ..."
"$bin" nightly --suite "$suite" --out "$out/baseline-run" --baseline "$baselines" --update-baseline >"$out/baseline-run.log" 2>&1
for r in $(seq 2 "$baseline_runs"); do
  "$bin" nightly --suite "$suite" --out "$out/baseline-run-$r" --baseline "$baselines" --add-timing-run >"$out/baseline-run-$r.log" 2>&1
done
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
print(f'{"nights":24} {"runs":>4} {"flagged runs":>12} {"light_tiles flagged":>19} {"scenario-nights":>15} '
      f'{"other flags":>11} {"not judged (loaded)":>19} {"wait share":>10} {"light_tiles ratio":>17}')
for key, rs in groups.items():
    tiles = sum(any(f.endswith("/light_tiles") for f in r["flagged"]) for r in rs)
    tiles_scenarios = sum(sum(f.endswith("/light_tiles") for f in r["flagged"]) for r in rs)
    other = sum(sum(not f.endswith("/light_tiles") and not f.endswith("/pipeline_total") for f in r["flagged"]) for r in rs)
    ratios = sorted(r["light_tiles_ratio_median"] for r in rs if r["light_tiles_ratio_median"] is not None)
    shares = sorted(r["wait_share_median"] for r in rs if r["wait_share_median"] is not None)
    line = {"nights": key, "runs": len(rs), "flagged_runs": sum(bool(r["flagged"]) for r in rs),
            "light_tiles_flagged_runs": tiles, "light_tiles_flagged_scenario_nights": tiles_scenarios,
            "scenario_nights": sum(r["scenarios"] for r in rs), "other_series_flagged": other,
            "scenario_nights_not_judged_loaded": sum(r["scenarios_not_judged_loaded"] for r in rs),
            "wait_share_median": shares[len(shares) // 2] if shares else None,
            "light_tiles_ratio_median": ratios[len(ratios) // 2] if ratios else None,
            "seconds_per_night": sum(r["seconds"] for r in rs) / len(rs)}
    table.append(line)
    fmt = lambda x: "-" if x is None else f"{x:.3f}"
    print(f'{key:24} {len(rs):4} {line["flagged_runs"]:12} {tiles:19} {tiles_scenarios:>7} of {line["scenario_nights"]:<4} '
          f'{other:11} {line["scenario_nights_not_judged_loaded"]:19} {fmt(line["wait_share_median"]):>10} '
          f'{fmt(line["light_tiles_ratio_median"]):>17}')
json.dump({"nights": rows, "table": table}, open(f"{out}/timing-verdicts.json", "w"), indent=1)
EOF
echo "record: $out/timing-verdicts.json"
