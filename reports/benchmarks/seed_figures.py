#!/usr/bin/env python3
"""Per-seed verdicts and messages of a `nightly --seeds N` output (or its
shards): one line per scenario, seed and check. Usage:
    seed_figures.py OUT_DIR [OUT_DIR ...]"""
import json
import pathlib
import sys

for root in sys.argv[1:]:
    for summary in sorted(pathlib.Path(root).glob("**/summary.json")):
        try:
            s = json.load(open(summary))
        except (OSError, ValueError):
            continue
        if "checks" not in s or "scenario" not in s:
            continue  # a suite's summary
        seed = s.get("resolved", {}).get("seed", s.get("seed", "?"))
        for c in s["checks"]:
            if c["name"] == "finite":
                continue
            print(f"{s['scenario']['name']}\t{seed}\t{c['name']}\t{c['verdict']}\t{c.get('message', '')}")
