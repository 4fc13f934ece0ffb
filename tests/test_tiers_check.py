#!/usr/bin/env python3
"""The test tiers (tests/CMakeLists.txt) cover the whole suite, held in CI.

Tiers, each a ctest label: unit, gpu, e2e, statistical, timing. Every ctest
has exactly one of them (so the five -L runs together are the whole suite and
none runs a test twice); every test of the two GoogleTest executables is a
ctest (a suite or test that tests/CMakeLists.txt puts in no tier is never
registered, and is named here); no name is registered twice; and no test is
DISABLED_ (a disabled test runs in no tier: make it a test, or a Google
Benchmark in tests/bench/).

Usage: tests/test_tiers_check.py BUILD_DIR CTEST UNIT_TESTS_EXE TESTS_EXE
       tests/test_tiers_check.py --self-test   (fires on an unregistered, an
                                               unlabelled, a doubly labelled,
                                               a twice registered and a
                                               disabled test; quiet on a
                                               clean suite)
Exit 0 with one line per tier (its count); exit 1 listing each finding.
"""
import json
import os
import subprocess
import sys

TIERS = ["unit", "gpu", "e2e", "statistical", "timing"]


def gtest_names(exe):
    """Suite.Test names as --gtest_list_tests prints them (parameters included)."""
    out = subprocess.run([exe, "--gtest_list_tests"], check=True, capture_output=True, text=True).stdout
    names, suite = [], None
    for line in out.splitlines():
        if not line.strip():
            continue
        if not line.startswith(" "):
            suite = line.split("#")[0].strip()
        else:
            names.append(suite + line.split("#")[0].strip())
    return names


def ctest_tests(build_dir, ctest):
    """(name, [labels]) of every ctest, from ctest's JSON listing. A GoogleTest
    test is named by the test its command runs (--gtest_filter=Suite.Test):
    gtest_discover_tests names a parameterised test by its parameter's
    printout instead, and the check compares GoogleTest's own names."""
    out = subprocess.run([ctest, "--test-dir", build_dir, "-N", "--show-only=json-v1"], check=True,
                         capture_output=True, text=True).stdout
    tests = []
    for t in json.loads(out)["tests"]:
        labels = []
        for p in t.get("properties", []):
            if p["name"] == "LABELS":
                labels = list(p["value"])
        name = t["name"]
        command = t.get("command", [])
        for arg in command:
            if arg.startswith("--gtest_filter="):
                name = os.path.basename(command[0]) + ":" + arg[len("--gtest_filter="):]
        tests.append((name, labels))
    return tests


def findings(gtests, ctests):
    found = []
    registered = {}
    for name, labels in ctests:
        registered[name] = registered.get(name, 0) + 1
        tiers = [l for l in labels if l in TIERS]
        others = [l for l in labels if l not in TIERS and any(t in l for t in TIERS)]
        if len(tiers) != 1:
            found.append(f"{name}: {len(tiers)} tier labels {tiers} (exactly one of {', '.join(TIERS)})")
        if others:
            found.append(f"{name}: label(s) {others} hold a tier's name, and ctest -L matches a regular expression")
    for name, n in registered.items():
        if n > 1:
            found.append(f"{name}: registered {n} times (in two tiers' lists of tests/CMakeLists.txt?)")
    for name in gtests:
        if "DISABLED_" in name:
            found.append(f"{name}: disabled, so it runs in no tier (make it a test, or a benchmark in tests/bench/)")
        elif name not in registered:
            found.append(f"{name}: in no tier, so no ctest runs it (add its suite or its name to one of the "
                         f"giharness_tests_<tier> lists in tests/CMakeLists.txt)")
    return found


def self_test():
    gtests = ["A.One", "A.Two", "B.One", "C.One", "Cli/P.Case/0"]
    clean = [("A.One", ["unit"]), ("A.Two", ["gpu"]), ("B.One", ["e2e"]), ("C.One", ["statistical"]),
             ("Cli/P.Case/0", ["timing"]), ("Script.Check", ["unit"])]
    cases = {
        "unregistered": (gtests + ["D.New"], clean),
        "unlabelled": (gtests, clean[:-1] + [("Script.Check", [])]),
        "doubly labelled": (gtests, clean[:1] + [("A.Two", ["gpu", "e2e"])] + clean[2:]),
        "registered twice": (gtests, clean + [("A.One", ["unit"])]),
        "disabled": (gtests + ["A.DISABLED_Timing"], clean),
        "label holding a tier's name": (gtests, clean + [("E.One", ["unit", "needs-gpu"])]),
    }
    ok = not findings(gtests, clean)
    fired = []
    for what, (g, c) in cases.items():
        f = findings(g, c)
        fired.append(f"{what}: {len(f)}")
        ok = ok and len(f) >= 1
    print(f"tier check self-test: {'pass' if ok else 'FAIL'} (clean suite: {len(findings(gtests, clean))} "
          f"findings; {'; '.join(fired)})")
    return 0 if ok else 1


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 5:
        print(__doc__, file=sys.stderr)
        return 2
    build_dir, ctest, unit_exe, tests_exe = sys.argv[1:]
    # Each test as "executable:Suite.Test", as ctest_tests names those it runs.
    names = {exe: [os.path.basename(exe) + ":" + n for n in gtest_names(exe)] for exe in (unit_exe, tests_exe)}
    gtests = names[unit_exe] + names[tests_exe]
    ctests = ctest_tests(build_dir, ctest)
    found = findings(gtests, ctests)
    labels = dict(ctests)
    for name in names[unit_exe]:
        if name in labels and labels[name] != ["unit"]:
            found.append(f"{name}: in giharness_unit_tests but labelled {labels[name]}")
    both = {n.split(":", 1)[1] for n in names[unit_exe]} & {n.split(":", 1)[1] for n in names[tests_exe]}
    for name in sorted(both):
        found.append(f"{name}: built into both executables (a file in the unit list and the rest?)")
    for line in found:
        print(line)
    counts = {t: sum(1 for _, l in ctests if t in l) for t in TIERS}
    print(f"{len(ctests)} ctests: " + ", ".join(f"{t} {counts[t]}" for t in TIERS) +
          f"; {len(gtests)} GoogleTest tests; {len(found)} findings")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
