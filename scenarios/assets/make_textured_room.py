#!/usr/bin/env python3
"""Writes textured_room.gltf: a small closed room whose every texture kind
changes what a renderer must compute (acceptance scene).

 - floor: a checker base colour (sRGB), tiled 3x by KHR_texture_transform;
 - back wall: a normal map of deep horizontal grooves, lit at a grazing angle
   by the ceiling panel near it (no TANGENT: the importer generates them);
 - a block: a metallic-roughness texture of stripes (metal/smooth against
   dielectric/rough);
 - the ceiling panel: an emissive texture (a bright ring on a dim field).
Everything (buffer, PNGs) is embedded as data: URIs, so the file stands alone.
`--mirror` writes textured_mirror_room.gltf: the same room with a mirror on
the left wall that shows the grooved wall, for the faults that touch only
surfaces seen through a ray hit (Bevy #24880). `--ridged-metal` writes
textured_ridged_mirror_room.gltf: the mirror room with the back wall a
glossy metal whose normal map leans towards the tangent (Bevy #23948's
skewed frame).
Deterministic: `python3 make_textured_room.py [--mirror | --ridged-metal] > /dev/null`
rewrites the same bytes. Run from scenarios/assets/."""
import base64
import json
import math
import os
import struct
import sys
import zlib


def png(width, height, pixel):
    """An RGBA8 PNG of pixel(x, y) -> (r, g, b, a)."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows.extend(pixel(x, y))
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(rows), 9)) +
            chunk(b"IEND", b""))


def checker(x, y):
    on = ((x // 8) + (y // 8)) % 2 == 0
    return (230, 225, 210, 255) if on else (40, 60, 110, 255)


def grooves(x, y):
    # A groove every 16 texels: the surface tilts ±45° about the tangent across
    # each groove's flanks, so the normal leans towards +v then -v.
    phase = (y % 16) / 16.0
    tilt = 0.0
    if phase < 0.25:
        tilt = 0.9
    elif phase < 0.5:
        tilt = -0.9
    n = (0.0, tilt, 1.0)
    length = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    return tuple(int(round((c / length * 0.5 + 0.5) * 255)) for c in n) + (255,)


def ridges(x, y):
    # A ridge every 16 texels along u: the normal leans 30° towards +u, then
    # -u, i.e. towards the tangent (grooves() leans it towards the bitangent).
    tilt = 0.577 if (x % 16) < 8 else -0.577
    n = (tilt, 0.0, 1.0)
    length = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    return tuple(int(round((c / length * 0.5 + 0.5) * 255)) for c in n) + (255,)


def stripes(x, y):
    metal = (x // 16) % 2 == 0
    # glTF: G roughness, B metallic.
    return (0, 50, 255, 255) if metal else (0, 230, 0, 255)


def ring(x, y):
    r = math.hypot(x - 31.5, y - 31.5)
    bright = 18 <= r <= 28
    return (255, 255, 255, 255) if bright else (60, 60, 60, 255)


def box(lo, hi):
    """A closed box, faces outward: positions, normals, uvs (metres), indices."""
    P, N, T, I = [], [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            u_axis, v_axis = [(1, 2), (2, 0), (0, 1)][axis]
            if sign < 0:
                u_axis, v_axis = v_axis, u_axis
            base = len(P)
            for (a, b) in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = hi[axis] if sign > 0 else lo[axis]
                p[u_axis] = hi[u_axis] if a else lo[u_axis]
                p[v_axis] = hi[v_axis] if b else lo[v_axis]
                n = [0.0, 0.0, 0.0]
                n[axis] = float(sign)
                P.append(p)
                N.append(n)
                T.append([p[u_axis] - lo[u_axis], hi[v_axis] - p[v_axis]])
            I += [base, base + 1, base + 2, base, base + 2, base + 3]
    return P, N, T, I


def quad(corner, du, dv, normal, uv_scale):
    """One two-sided-free quad: corner + s·du + t·dv, counter-clockwise seen from normal."""
    P, N, T = [], [], []
    for (s, t) in ((0, 0), (1, 0), (1, 1), (0, 1)):
        P.append([corner[i] + s * du[i] + t * dv[i] for i in range(3)])
        N.append(list(normal))
        T.append([s * uv_scale[0], (1 - t) * uv_scale[1]])
    return P, N, T, [0, 1, 2, 0, 2, 3]


def main():
    W, H, D = 4.0, 3.0, 4.0  # room: x in [-2, 2], y in [0, 3], z in [-4, 0]
    meshes = {
        # The floor, walls and ceiling face into the room.
        "floor": quad([-W / 2, 0, 0], [W, 0, 0], [0, 0, -D], [0, 1, 0], (1, 1)),
        "back_wall": quad([-W / 2, 0, -D], [W, 0, 0], [0, H, 0], [0, 0, 1], (W, H)),
        "left_wall": quad([-W / 2, 0, 0], [0, 0, -D], [0, H, 0], [1, 0, 0], (1, 1)),
        "right_wall": quad([W / 2, 0, -D], [0, 0, D], [0, H, 0], [-1, 0, 0], (1, 1)),
        "ceiling": quad([-W / 2, H, -D], [W, 0, 0], [0, 0, D], [0, -1, 0], (1, 1)),
        "front_wall": quad([W / 2, 0, 0], [-W, 0, 0], [0, H, 0], [0, 0, -1], (1, 1)),
        "block": box([0.3, 0.0, -2.6], [1.3, 1.2, -1.6]),
        # The panel hangs 5 cm below the ceiling, 40 cm from the back wall, facing down.
        "panel": quad([-1.0, H - 0.05, -D + 0.4], [2.0, 0, 0], [0, 0, 0.6], [0, -1, 0], (1, 1)),
    }
    materials = [
        {"name": "checker_floor", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [3, 3]}}},
            "metallicFactor": 0.0, "roughnessFactor": 0.9}},
        {"name": "grooved_wall", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1],
            "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "normalTexture": {"index": 1}},
        {"name": "plain_wall", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1],
            "metallicFactor": 0.0, "roughnessFactor": 1.0}},
        {"name": "striped_block", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.3, 1],
            "metallicFactor": 1.0, "roughnessFactor": 1.0, "metallicRoughnessTexture": {"index": 2}}},
        {"name": "ring_panel", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
         "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 3},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12.0}}},
    ]
    ridged = "--ridged-metal" in sys.argv[1:]
    mirror = ridged or "--mirror" in sys.argv[1:]
    if mirror:
        # 1 cm off the left wall, facing +x, from z -3.9 to -1.9: seen from the
        # camera at about 50 degrees, it reflects the back wall's left half.
        meshes["mirror"] = quad([-W / 2 + 0.01, 0.3, -1.9], [0, 0, -2.0], [0, 2.4, 0], [1, 0, 0], (1, 1))
        materials.append({"name": "mirror", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.95, 0.95, 1],
                          "metallicFactor": 1.0, "roughnessFactor": 0.0}})
    material_of = {"mirror": 5, "floor": 0, "back_wall": 1, "left_wall": 2, "right_wall": 2, "ceiling": 2, "front_wall": 2,
                   "block": 3, "panel": 4}
    images = [png(64, 64, checker), png(64, 64, grooves), png(64, 64, stripes), png(64, 64, ring)]
    textures = [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}, {"source": 2, "sampler": 0},
                {"source": 3, "sampler": 1}]
    if ridged:
        # The back wall a mirror-smooth metal whose ridges lean the
        # normal towards the tangent: the wall the mirror shows.
        materials.append({"name": "ridged_metal", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                          "metallicFactor": 1.0, "roughnessFactor": 0.0}, "normalTexture": {"index": 4}})
        material_of["back_wall"] = len(materials) - 1
        images.append(png(64, 64, ridges))
        textures.append({"source": 4, "sampler": 0})

    blob = bytearray()
    views, accessors, gltf_meshes, nodes = [], [], [], []

    def add_view(data, target):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(views) - 1

    def add_accessor(values, kind):
        flat = [c for v in values for c in v]
        data = struct.pack("<%df" % len(flat), *flat)
        acc = {"bufferView": add_view(data, 34962), "componentType": 5126, "count": len(values), "type": kind}
        if kind == "VEC3":
            acc["min"] = [min(v[i] for v in values) for i in range(3)]
            acc["max"] = [max(v[i] for v in values) for i in range(3)]
        accessors.append(acc)
        return len(accessors) - 1

    for name, (P, N, T, I) in meshes.items():
        attributes = {"POSITION": add_accessor(P, "VEC3"), "NORMAL": add_accessor(N, "VEC3"),
                      "TEXCOORD_0": add_accessor(T, "VEC2")}
        index_view = add_view(struct.pack("<%dI" % len(I), *I), 34963)
        accessors.append({"bufferView": index_view, "componentType": 5125, "count": len(I), "type": "SCALAR"})
        gltf_meshes.append({"name": name, "primitives": [
            {"attributes": attributes, "indices": len(accessors) - 1, "material": material_of[name]}]})
        nodes.append({"name": name, "mesh": len(gltf_meshes) - 1})
    # The camera in the open doorway's place (the front wall is there: the
    # camera sits inside the room, at its front), looking at the back wall.
    nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 1.5, -0.3]})

    gltf = {
        "asset": {"version": "2.0", "generator": "giharness scenarios/assets/make_textured_room.py"},
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": gltf_meshes,
        "materials": materials,
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.1, "znear": 0.01, "aspectRatio": 1.777}}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}, {"wrapS": 33071, "wrapT": 33071}],
        "textures": textures,
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(p).decode("ascii")} for p in images],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode("ascii")}],
    }
    name = "textured_ridged_mirror_room.gltf" if ridged else "textured_mirror_room.gltf" if mirror else "textured_room.gltf"
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main()
