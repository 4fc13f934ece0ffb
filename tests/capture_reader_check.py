"""The capture reader (python/giharness_capture.py) against a real capture.

    capture_reader_check.py READER_DIR CAPTURE_DIR

Fails (exit 1, naming what) unless
- every buffer whose layout names a struct of a shared header carries fields;
- every named field equals the raw words at the offsets the manifest gives;
- the fields land where the structs' comments say (an independent statement:
  DiReservoir's M and W are words 4 and 5, GiReservoir's sample position is
  words 0-2 and its M word 3, its W word 11; GBufferTexel's geometric normal
  words 4-6), as the README's one-liner read them before there were fields;
- a manifest without fields (a capture of before) reads as the raw words.
"""
import json
import os
import re
import shutil
import sys
import tempfile

import numpy as np

sys.path.insert(0, sys.argv[1])
from giharness_capture import load_capture  # noqa: E402

failures = []


def expect(ok, what):
    if not ok:
        failures.append(what)


capture_dir = sys.argv[2]
cap = load_capture(capture_dir)
for b in cap.manifest["buffers"]:
    name = b["name"]
    if re.match(r"^\w+ \((core|gpu)/.*\.h\)$", b.get("layout", "")):
        expect(b.get("fields"), "%s (%s) carries no fields" % (name, b["layout"]))
    fields = b.get("fields")
    if not fields:
        expect(cap[name].dtype == cap.raw[name].dtype, "%s without fields is not its raw array" % name)
        continue
    raw = cap.raw[name]
    words_u = np.ascontiguousarray(raw).view(np.uint32)
    for f in fields:
        lo, hi = f["offset"] // 4, f["offset"] // 4 + f["count"]
        expected = words_u[..., lo:hi].view(np.dtype(f["dtype"]))
        got = np.asarray(cap[name][f["name"]])
        got = got.reshape(expected.shape)
        expect(np.array_equal(got.view(np.uint32), expected.view(np.uint32)),
               "%s.%s differs from raw words %d:%d" % (name, f["name"], lo, hi))

as_float = lambda a: np.ascontiguousarray(a).view(np.float32)
di = cap.raw["di/stored_reservoirs"]
expect(np.array_equal(cap["di/stored_reservoirs"]["confidence_weight"], as_float(di)[..., 4]), "DiReservoir M is not word 4")
expect(np.array_equal(cap["di/stored_reservoirs"]["unbiased_contribution_weight"], as_float(di)[..., 5]),
       "DiReservoir W is not word 5")
expect(np.array_equal(cap["di/stored_reservoirs"]["light.light_id"], di[..., 0]), "DiReservoir light id is not word 0")
gi = cap.raw["gi/stored_reservoirs"]
expect(np.array_equal(cap["gi/stored_reservoirs"]["sample_position"][..., :3], gi[..., 0:3]),
       "GiReservoir sample position is not words 0-2")
expect(np.array_equal(cap["gi/stored_reservoirs"]["radiance"][..., 3], gi[..., 11]), "GiReservoir W is not word 11")
g = cap.raw["gbuffer/texels"]
expect(np.array_equal(cap["gbuffer/texels"]["geometric_normal"][..., :3], g[..., 4:7]),
       "GBufferTexel geometric normal is not words 4-6")
# The reader is only worth its test where the values are not all zero.
expect(np.count_nonzero(cap["di/stored_reservoirs"]["unbiased_contribution_weight"]) > 0, "no DI reservoir has a W")
expect(np.count_nonzero(cap["gi/stored_reservoirs"]["radiance"][..., 3]) > 0, "no GI reservoir has a W")

# A capture written before the manifest carried fields: raw words throughout.
old = tempfile.mkdtemp(prefix="giharness-old-capture-")
try:
    for f in os.listdir(capture_dir):
        if f.endswith(".npy") or f == "manifest.json":
            shutil.copy(os.path.join(capture_dir, f), old)
    with open(os.path.join(old, "manifest.json")) as fh:
        m = json.load(fh)
    for b in m["buffers"]:
        b.pop("fields", None)
    with open(os.path.join(old, "manifest.json"), "w") as fh:
        json.dump(m, fh)
    old_cap = load_capture(old)
    for name, raw in cap.raw.items():
        expect(np.array_equal(old_cap[name], raw) and old_cap[name].dtype == raw.dtype,
               "%s of a capture without fields is not its raw words" % name)
finally:
    shutil.rmtree(old)

checked = sum(len(b.get("fields") or []) for b in cap.manifest["buffers"])
if failures:
    print("\n".join("FAIL: " + f for f in failures))
    sys.exit(1)
print("capture reader: %d fields of %d buffers equal their raw words" % (checked, len(cap.buffers)))
