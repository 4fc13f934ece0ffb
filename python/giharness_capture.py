"""Reads a giharness frame capture (replay/capture.h documents the folder).

    import sys; sys.path.insert(0, "/usr/share/giharness/python")   # or <build>/share/giharness/python
    from giharness_capture import load_capture
    cap = load_capture("out/tour/captures/frame_00015")
    di = cap.buffers["di/stored_reservoirs"]          # shape (chains, h, w), named fields
    di["unbiased_contribution_weight"][0, y, x]       # W of chain 0's reservoir at pixel (x, y)
    cap.buffers["gi/stored_reservoirs"]["sample_position"][0, y, x, :3]

Each buffer whose manifest entry carries "fields" (the struct's members as the
C++ describes them, gpu/state_layouts.cpp) is a numpy structured array: the
innermost axis (one struct's words) becomes the record, so the array's shape
is the buffer's shape without it. A field of several components (a vec4, a
uint[32]) is a sub-array. Buffers without fields (descriptions such as
"rgb sum, w samples", and every buffer of a capture written before the
manifest carried fields) are the raw arrays of their .npy files.

Standard library and numpy only.
"""

import json
import os

import numpy as np

__all__ = ["Capture", "load_capture", "struct_dtype"]


class Capture:
    """A capture folder: its manifest, and every buffer by name."""

    def __init__(self, directory, manifest, buffers, raw):
        self.dir = directory
        self.manifest = manifest
        self.frame = manifest.get("frame")
        self.buffers = buffers  # name -> structured array (fields) or raw array
        self.raw = raw          # name -> the .npy's array as stored (words)

    def fields(self, name):
        """The manifest's field list of buffer `name` ([] without one)."""
        for b in self.manifest["buffers"]:
            if b["name"] == name:
                return b.get("fields") or []
        raise KeyError(name)

    def __getitem__(self, name):
        return self.buffers[name]

    def __contains__(self, name):
        return name in self.buffers

    def __repr__(self):
        return "Capture(%r, frame %s, %d buffers)" % (self.dir, self.frame, len(self.buffers))


def struct_dtype(fields, itemsize):
    """numpy dtype of one struct: each field at its byte offset, `itemsize` bytes."""
    names, formats, offsets = [], [], []
    for f in fields:
        names.append(f["name"])
        formats.append((f["dtype"], (f["count"],)) if f["count"] != 1 else f["dtype"])
        offsets.append(f["offset"])
    return np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": itemsize})


def _structured(raw, fields, name):
    if raw.ndim == 0:
        raise ValueError("%s: a struct buffer needs at least one axis" % name)
    itemsize = raw.shape[-1] * raw.dtype.itemsize
    end = max(f["offset"] + 4 * f["count"] for f in fields)
    if end > itemsize:
        raise ValueError("%s: fields end at byte %d, a row has %d" % (name, end, itemsize))
    rows = np.ascontiguousarray(raw).view(struct_dtype(fields, itemsize))
    return rows.reshape(raw.shape[:-1])


def load_capture(directory):
    """Every buffer of the capture at `directory`, by the manifest's names."""
    with open(os.path.join(directory, "manifest.json"), encoding="utf-8") as f:
        manifest = json.load(f)
    buffers, raw = {}, {}
    for b in manifest.get("buffers", []):
        array = np.load(os.path.join(directory, b["file"]), allow_pickle=False)
        raw[b["name"]] = array
        fields = b.get("fields")
        buffers[b["name"]] = _structured(array, fields, b["name"]) if fields else array
    return Capture(directory, manifest, buffers, raw)
