#!/usr/bin/env python3
"""The source tree's layering rule (docs/architecture.md, "Layers"), held in CI.

Layers, lowest first: core -> gpu -> reports -> checks -> replay -> app.
A file may include (#include "layer/...") only its own layer or a lower one:
nothing in core reaches Vulkan, the reports never reach a check, a check never
reaches the run engine (replay/: reruns, captures and the frame loop are its
work, asked for through CheckNeeds), and nothing but the command line
includes app/. tests/ may include anything.

Usage: tests/layering_check.py SOURCE_DIR
       tests/layering_check.py --self-test   (the rule fires on a check that
                                             includes the run engine, and
                                             stays quiet on one that does not)
Exit 0 with a one-line summary; exit 1 listing each include that breaks the
rule as file:line.
"""
import pathlib
import re
import sys

LAYERS = ["core", "gpu", "reports", "checks", "replay", "app"]
RANK = {name: i for i, name in enumerate(LAYERS)}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]*"')
SUFFIXES = {".h", ".cpp", ".glsl", ".comp"}


def violations(root: pathlib.Path):
    found, files = [], 0
    for layer in LAYERS:
        for path in sorted((root / layer).rglob("*")):
            if path.suffix not in SUFFIXES or not path.is_file():
                continue
            files += 1
            for n, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if m and m.group(1) in RANK and RANK[m.group(1)] > RANK[layer]:
                    found.append(f"{path.relative_to(root)}:{n}: {layer}/ includes {m.group(1)}/ "
                                 f"({' -> '.join(LAYERS)}: a layer includes only itself and those before it)")
    return found, files


def self_test() -> int:
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for layer in LAYERS:
            (root / layer).mkdir()
        (root / "replay/run_scenario.h").write_text("#pragma once\n")
        (root / "checks/x_check.cpp").write_text('#include "checks/check.h"\n#include "core/scenario.h"\n')
        clean, _ = violations(root)
        (root / "checks/x_check.cpp").write_text('#include "checks/check.h"\n  #  include "replay/run_scenario.h"\n')
        (root / "core/y.h").write_text('#include "gpu/device.h"\n')
        broken, _ = violations(root)
    ok = not clean and sorted(b.split(" ")[0] for b in broken) == ["checks/x_check.cpp:2:", "core/y.h:1:"]
    print(f"layering self-test: {'pass' if ok else 'FAIL'} (clean tree: {len(clean)} findings, broken: {broken})")
    return 0 if ok else 1


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-4], file=sys.stderr)
        return 2
    root = pathlib.Path(sys.argv[1])
    missing = [layer for layer in LAYERS if not (root / layer).is_dir()]
    if missing:
        print(f"layering: {root} has no {', '.join(missing)}/ (a layer moved? update LAYERS)", file=sys.stderr)
        return 2
    found, files = violations(root)
    for v in found:
        print(v)
    if found:
        print(f"layering: {len(found)} includes break the rule in {files} files")
        return 1
    print(f"layering: {files} files, every include within its layer or below ({' -> '.join(LAYERS)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
