#!/usr/bin/env python3
"""Writes glossy_room.gltf next to this script (python3 standard library only,
deterministic: the same bytes on every run).

A room 4 m wide, 3 m high and 4 m deep, open at the front (+Z) like a Cornell
box: white diffuse floor and walls, a grey ceiling, an emissive quad just under
the ceiling facing down (radiance 10 = emissiveFactor 1 x
KHR_materials_emissive_strength 10), a rough dielectric sphere and a glossy
metal sphere under a "props" parent node (translated and turned about +Y), a
camera looking into the room, and a KHR_lights_punctual directional light
entering through the open front at an angle (3 lux, angular radius 0.02 rad in
the light's extras).

Units: metres, +Y up, counter-clockwise front faces (glTF conventions).
Run:  python3 scenarios/assets/make_glossy_room.py
"""
import base64
import json
import math
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "glossy_room.gltf")


class Buffer:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def _view(self, payload, target):
        while len(self.data) % 4:
            self.data.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload), "target": target})
        self.data += payload
        return len(self.views) - 1

    def vec3(self, values):
        flat = [c for v in values for c in v]
        view = self._view(struct.pack("<%df" % len(flat), *flat), 34962)
        # min/max of the float32 values actually stored
        stored = [struct.unpack("<f", struct.pack("<f", c))[0] for c in flat]
        lo = [min(stored[i::3]) for i in range(3)]
        hi = [max(stored[i::3]) for i in range(3)]
        self.accessors.append({"bufferView": view, "componentType": 5126, "count": len(values), "type": "VEC3",
                               "min": lo, "max": hi})
        return len(self.accessors) - 1

    def indices(self, values):
        top = max(values)
        fmt, comp = ("B", 5121) if top < 256 else ("H", 5123) if top < 65536 else ("I", 5125)
        view = self._view(struct.pack("<%d%s" % (len(values), fmt), *values), 34963)
        self.accessors.append({"bufferView": view, "componentType": comp, "count": len(values), "type": "SCALAR"})
        return len(self.accessors) - 1


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(a):
    n = math.sqrt(sum(c * c for c in a))
    return [c / n for c in a]


def quad(positions, normals, indices, a, b, c, d):
    """Quad a-b-c-d, counter-clockwise seen from the front, flat normals."""
    n = normalize(cross(sub(b, a), sub(c, a)))
    base = len(positions)
    positions += [a, b, c, d]
    normals += [n, n, n, n]
    indices += [base, base + 1, base + 2, base, base + 2, base + 3]


def uv_sphere(radius, segments, rings):
    positions, normals, indices = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2.0 * math.pi * s / segments
            n = [math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi)]
            normals.append([round(c, 7) for c in n])
            positions.append([round(radius * c, 7) for c in n])
    for r in range(rings):
        for s in range(segments):
            i0 = r * (segments + 1) + s
            i1 = i0 + segments + 1
            # counter-clockwise seen from outside
            if r != 0:
                indices += [i0, i1, i0 + 1]
            if r != rings - 1:
                indices += [i0 + 1, i1, i1 + 1]
    return positions, normals, indices


def quat_axis_angle(axis, angle):
    axis = normalize(axis)
    s = math.sin(angle / 2)
    return [round(axis[0] * s, 9), round(axis[1] * s, 9), round(axis[2] * s, 9), round(math.cos(angle / 2), 9)]


def quat_from_z_to(d):
    """Unit quaternion (x, y, z, w) turning +Z onto the unit vector d."""
    z = [0.0, 0.0, 1.0]
    axis = cross(z, d)
    angle = math.acos(max(-1.0, min(1.0, d[2])))
    return quat_axis_angle(axis, angle)


def main():
    buf = Buffer()
    W, H, D = 2.0, 3.0, 2.0  # half width, height, half depth

    # Room: floor, back, left, right (white) + ceiling (grey), all facing in.
    pos, nrm, ind = [], [], []
    quad(pos, nrm, ind, [-W, 0, D], [W, 0, D], [W, 0, -D], [-W, 0, -D])  # floor, +Y
    quad(pos, nrm, ind, [-W, 0, -D], [W, 0, -D], [W, H, -D], [-W, H, -D])  # back, +Z
    quad(pos, nrm, ind, [-W, 0, D], [-W, 0, -D], [-W, H, -D], [-W, H, D])  # left, +X
    quad(pos, nrm, ind, [W, 0, -D], [W, 0, D], [W, H, D], [W, H, -D])  # right, -X
    walls = (buf.vec3(pos), buf.vec3(nrm), buf.indices(ind))
    pos, nrm, ind = [], [], []
    quad(pos, nrm, ind, [-W, H, -D], [W, H, -D], [W, H, D], [-W, H, D])  # ceiling, -Y
    ceiling = (buf.vec3(pos), buf.vec3(nrm), buf.indices(ind))

    # Light: a 1.2 m square facing down, non-indexed (exercises that path).
    L = 0.6
    a, b, c, d = [-L, 0, -L], [L, 0, -L], [L, 0, L], [-L, 0, L]
    light_pos = [a, b, c, a, c, d]
    light_nrm = [[0.0, -1.0, 0.0]] * 6
    light = (buf.vec3(light_pos), buf.vec3(light_nrm))

    # One unit-radius-0.5 UV sphere shared by both sphere meshes.
    sp, sn, si = uv_sphere(0.5, 32, 16)
    sphere = (buf.vec3(sp), buf.vec3(sn), buf.indices(si))

    materials = [
        {"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
                                                   "roughnessFactor": 1.0}},
        {"name": "grey_ceiling", "pbrMetallicRoughness": {"baseColorFactor": [0.4, 0.4, 0.4, 1.0],
                                                          "metallicFactor": 0.0, "roughnessFactor": 1.0}},
        {"name": "emitter", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
                                                     "roughnessFactor": 1.0},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10.0}}},
        {"name": "rough_dielectric", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1.0],
                                                              "metallicFactor": 0.0, "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_specular": {"specularFactor": 1.0}}},
        {"name": "glossy_metal", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.8, 0.5, 1.0],
                                                          "metallicFactor": 1.0, "roughnessFactor": 0.3}},
    ]

    def prim(p, n, i, material):
        out = {"attributes": {"POSITION": p, "NORMAL": n}, "material": material, "mode": 4}
        if i is not None:
            out["indices"] = i
        return out

    meshes = [
        {"name": "room", "primitives": [prim(*walls, 0), prim(*ceiling, 1)]},
        {"name": "light", "primitives": [prim(light[0], light[1], None, 2)]},
        {"name": "sphere_dielectric", "primitives": [prim(*sphere, 3)]},
        {"name": "sphere_metal", "primitives": [prim(*sphere, 4)]},
    ]

    sun_dir = normalize([-0.35, 0.45, 1.0])  # towards the light: from the front, above, slightly left
    nodes = [
        {"name": "room", "mesh": 0},
        {"name": "ceiling_light", "mesh": 1, "translation": [0.0, H - 0.01, 0.0]},
        {"name": "props", "translation": [0.0, 0.0, -0.4], "rotation": quat_axis_angle([0, 1, 0], math.radians(30)),
         "children": [3, 4]},
        {"name": "dielectric_sphere", "mesh": 2, "translation": [-0.9, 0.5, 0.2]},
        {"name": "metal_sphere", "mesh": 3, "translation": [0.9, 0.4, -0.3], "scale": [0.8, 0.8, 0.8]},
        {"name": "camera", "camera": 0, "translation": [0.0, 1.5, 6.2],
         "rotation": quat_axis_angle([1, 0, 0], math.radians(-4))},
        {"name": "sun", "rotation": quat_from_z_to(sun_dir),
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
    ]

    data = bytes(buf.data)
    gltf = {
        "asset": {"version": "2.0", "generator": "giharness make_glossy_room.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"name": "glossy_room", "nodes": [0, 1, 2, 5, 6]}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 0.7, "aspectRatio": 1.0, "znear": 0.05}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "color": [1.0, 0.96, 0.9], "intensity": 3.0,
             "extras": {"angular_radius": 0.02}}]}},
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")}],
        "bufferViews": buf.views,
        "accessors": buf.accessors,
    }
    text = json.dumps(gltf, indent=1, sort_keys=False) + "\n"
    with open(OUT, "w", encoding="ascii", newline="\n") as f:
        f.write(text)
    print("wrote %s (%d bytes)" % (OUT, len(text)))


if __name__ == "__main__":
    main()
