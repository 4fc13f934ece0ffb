#!/usr/bin/env python3
"""Speed against error at equal time: one row per realtime run from
the "equal_time" block of its summary.json (giharness run --equal-time, or any
nightly). Prints a Markdown table; with --json FILE also writes the rows and
each run's device and build as one record.

usage: equal_time_table.py [--json FILE] SUMMARY.json...
"""
import json
import sys


def fig(v):
    return "–" if v is None else f"{v:.3g}"


def peer(p):
    """relMSE (spp, ms); † where one sample costs more than the realtime frame."""
    if not p:
        return "–"
    return f"{fig(p.get('relmse'))} ({p.get('spp')} spp, {fig(p.get('ms'))} ms{'' if p.get('fits_budget', True) else ' †'})"


def main(argv):
    out = None
    if argv[:1] == ["--json"]:
        out, argv = argv[1], argv[2:]
    rows, record = [], []
    for path in argv:
        s = json.load(open(path))
        e = s.get("equal_time")
        if not e:
            continue
        rt, g, m = e["realtime"], e.get("gpu_path_tracer", {}), e.get("embree", {})
        sig = e.get("signals") or {}
        rows.append(
            f"| {s['scenario']['name']} | {'DI' if e['reference']['direct_only'] else 'DI+GI+spec'} "
            f"| {fig(rt['ms_per_frame'])} | {fig(rt['frame_relmse'])} "
            f"| {peer(g)} | {peer(m)} "
            f"| {fig(g.get('equal_error_time_ratio_frame'))} | {fig(m.get('equal_error_time_ratio_frame'))} "
            f"| {fig(rt['temporal_relmse'])} ({rt['window_frames']}) | {fig(g.get('equal_error_time_ratio_temporal'))} "
            f"| {fig(e['reference']['noise_relmse'])} |")
        record.append({"scenario": s["scenario"]["name"], "file": s["scenario"]["file"], "device": s["device"],
                       "backend": s["resolved"]["backend"], "resolution": s["resolved"]["resolution"],
                       "equal_time": e, "timings": s["timings"].get("frame")})
    print("| scenario | output | realtime ms/frame | realtime relMSE (frame) | GPU path tracer relMSE | "
          "Embree relMSE | equal-error time ratio, GPU PT | equal-error time ratio, Embree | "
          "realtime relMSE, temporal mean (frames) | equal-error time ratio, GPU PT, temporal | reference noise |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    if out:
        json.dump({"rows": record}, open(out, "w"), indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
