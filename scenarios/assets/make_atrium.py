#!/usr/bin/env python3
"""Writes a textured atrium, Sponza-like in layout, as glTF 2.0 (python3
standard library only, deterministic: the same bytes on every run).

The scene (units metres, +Y up, counter-clockwise front faces, every solid
closed, walls as boxes):
  - a court 20 m (X) x 10 m (Z), open to the sky (no ceiling over it);
  - on each long side (z = +-5) two storeys of arcades: square plinths, a
    cylindrical base ring and shaft, a capital, and half-circle arches
    (arch blocks with the real semicircular intrados) spanning the bays;
    storey 1 from 0 to 6 m, storey 2 from 6 to 12 m, a metal railing
    (rail + balusters) between the upper columns;
  - galleries 3 m deep behind the arcades: an intermediate slab at 6 m, a
    roof slab over each gallery at 12 m, back walls at z = +-8..8.5 and end
    walls at x = +-10..10.5, all boxes;
  - a tiled floor (grid-tessellated box top) over the whole building;
  - four emissive lamp boxes on metal brackets on the ground-floor piers;
  - a sun (KHR_lights_punctual directional light, "extras":
    {"angular_radius": 0.00465}) shining into the court at ~65 deg elevation;
  - a perspective camera at one end of the court looking along it (+X).

Materials (metallic-roughness): stone (baseColorTexture, sRGB ashlar pattern,
plus a tangent-space normalTexture, +Y up green) on walls, arches and
columns; a floor tile checker with KHR_texture_transform (scale); plaster on
the slabs through a MIRRORED_REPEAT sampler; metal railing and lamp fittings
with a metallicRoughnessTexture (G roughness, B metallic); lamps with an
emissiveTexture (CLAMP_TO_EDGE sampler) and KHR_materials_emissive_strength.
Extra materials (--materials M > 8) are tinted variants of the stone sharing
its textures, spread over the arch blocks and column parts.

Vertex attributes POSITION, NORMAL, TEXCOORD_0 (UVs in metres), u32 indices;
TANGENT only on the stone columns' cylinders (the other meshes leave the
tangents to the importer: MikkTSpace).

Options:
  --out DIR        output folder (default: atrium/ next to this script)
  --name NAME      file stem (default atrium): NAME.gltf + NAME.bin +
                   NAME_*.png, or NAME.glb with --glb
  --triangles N    target triangle count (default 30000); tessellation of
                   columns, arches, walls and floor is scaled to within a
                   few per cent of N
  --materials M    number of distinct materials (default 8, at least 8)
  --glb            one .glb with the buffer and images embedded
Every file is written under a temporary name and renamed into place.

Run:  python3 scenarios/assets/make_atrium.py            (the small atrium)
      python3 scenarios/assets/make_atrium.py --triangles 1000000 \\
          --materials 64 --glb --name atrium_1m --out scenarios/assets/generated
"""
import argparse
import array
import json
import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# ---- layout (metres) --------------------------------------------------------
COURT_X = 10.0          # court x in [-10, 10]
COURT_Z = 5.0           # arcade centre lines at z = +-5
BAYS = 5                # arcade bays per side and storey
BAY_W = 2 * COURT_X / BAYS
DEPTH = 0.8             # arcade (arch block, capital) thickness in z
PIER = 0.8              # capital width
ARCH_R = (BAY_W - PIER) / 2
STOREY = 6.0
SPRING = 4.0            # arch springing height above the storey floor
SHAFT_R = 0.28
RING_R = 0.38
PLINTH = 0.5            # plinth half width
GALLERY_Z = 8.0         # back walls from z = +-8 to +-8.5
WALL_T = 0.5
HEIGHT = 12.0
SLAB_T = 0.4
TEX = 256               # texture size


# ---- textures -----------------------------------------------------------------

def png_bytes(width, height, channels, rows):
    """rows: list of bytes, each width*channels long (8-bit RGB or RGBA)."""
    raw = b"".join(b"\x00" + r for r in rows)
    color_type = {3: 2, 4: 6}[channels]

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def hash01(x, y, s=0):
    h = (x * 374761393 + y * 668265263 + s * 2147483647) & 0xffffffff
    h = ((h ^ (h >> 13)) * 1274126177) & 0xffffffff
    return ((h ^ (h >> 16)) & 0xffff) / 65535.0


def clamp8(v):
    return 0 if v < 0 else 255 if v > 255 else int(v + 0.5)


def stone_height(x, y):
    """Ashlar courses: the texture (1 m x 1 m) holds 4 courses of 0.25 m and
    2 blocks of 0.5 m per course, each course offset by half a block. Returns
    (height in [0, 1]: 1 on a block face, 0 in a joint; block id)."""
    n = TEX
    course = (y * 4) // n
    yy = (y * 4) % n                      # 0..n-1 within the course
    off = (n // 4) if course % 2 else 0
    xs = (x + off) % n
    block = xs // (n // 2)
    xx = xs % (n // 2)
    joint = 6                             # joint width in pixels
    bevel = 5
    # yy spans the course scaled by 4: convert to pixels
    d = min(xx, n // 2 - 1 - xx, yy // 4, (n - 1 - yy) // 4)
    if d < joint // 2:
        h = 0.0
    elif d < joint // 2 + bevel:
        h = (d - joint // 2) / bevel
    else:
        h = 1.0
    return h, course * 2 + block


def make_stone_color():
    rows = []
    for y in range(TEX):
        r = bytearray()
        for x in range(TEX):
            h, b = stone_height(x, y)
            tone = 0.82 + 0.16 * hash01(b, 7)
            grain = 0.93 + 0.07 * hash01(x // 2, y // 2, 3)
            if h == 0.0:
                c = (150, 142, 130)
            else:
                c = (235 * tone * grain, 222 * tone * grain, 196 * tone * grain)
            r += bytes((clamp8(c[0]), clamp8(c[1]), clamp8(c[2])))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


def make_stone_normal():
    hmap = [[stone_height(x, y)[0] for x in range(TEX)] for y in range(TEX)]
    k = 3.0
    rows = []
    for y in range(TEX):
        r = bytearray()
        up, dn = hmap[(y - 1) % TEX], hmap[(y + 1) % TEX]
        row = hmap[y]
        for x in range(TEX):
            dhdx = (row[(x + 1) % TEX] - row[(x - 1) % TEX]) * 0.5
            dhdy_down = (dn[x] - up[x]) * 0.5        # image rows go down
            nx, ny, nz = -k * dhdx, k * dhdy_down, 1.0  # +Y = up in the image
            inv = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
            r += bytes((clamp8((nx * inv * 0.5 + 0.5) * 255), clamp8((ny * inv * 0.5 + 0.5) * 255),
                        clamp8((nz * inv * 0.5 + 0.5) * 255)))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


def make_floor_color():
    """4 x 4 tiles checker (two marbles) with thin grout lines."""
    rows = []
    t = TEX // 4
    for y in range(TEX):
        r = bytearray()
        for x in range(TEX):
            tx, ty = x // t, y // t
            if x % t < 2 or y % t < 2:
                c = (90, 88, 84)
            else:
                v = 0.9 + 0.1 * hash01(x // 4, y // 4, tx + 4 * ty)
                c = (200 * v, 196 * v, 186 * v) if (tx + ty) % 2 == 0 else (96 * v, 70 * v, 58 * v)
            r += bytes((clamp8(c[0]), clamp8(c[1]), clamp8(c[2])))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


def make_plaster_color():
    rows = []
    for y in range(TEX):
        r = bytearray()
        for x in range(TEX):
            v = 0.88 + 0.08 * hash01(x // 8, y // 8, 5) + 0.04 * hash01(x, y, 6)
            r += bytes((clamp8(228 * v), clamp8(220 * v), clamp8(205 * v)))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


def make_metal_mr():
    """R unused (255), G roughness: brushed bands 0.25..0.6, B metallic 1
    except a few bare 'rust' spots (0)."""
    rows = []
    for y in range(TEX):
        r = bytearray()
        band = 0.25 + 0.35 * hash01(0, y // 3, 9)
        for x in range(TEX):
            rust = hash01(x // 16, y // 16, 11) > 0.93
            rough = 0.85 if rust else band
            r += bytes((255, clamp8(rough * 255), 0 if rust else 255))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


def make_lamp_emissive():
    """A warm glow, brightest in the middle, a dark cross of lead bars."""
    rows = []
    c = (TEX - 1) / 2
    for y in range(TEX):
        r = bytearray()
        for x in range(TEX):
            if abs(x - c) < 6 or abs(y - c) < 6:
                r += b"\x30\x28\x20"
                continue
            d = math.hypot(x - c, y - c) / c
            v = 1.0 - 0.45 * min(d, 1.0)
            r += bytes((clamp8(255 * v), clamp8(214 * v), clamp8(150 * v)))
        rows.append(bytes(r))
    return png_bytes(TEX, TEX, 3, rows)


# ---- geometry -----------------------------------------------------------------

def vsub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def vcross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def vdot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def vnorm(a):
    n = math.sqrt(vdot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def plane_frame(n):
    """(right, up) of a face with outward normal n: seen from outside, u runs
    right and v down (glTF image convention), so textures are upright and
    unmirrored; tangent = right with w = +1."""
    up = (0.0, 0.0, -1.0) if n[1] > 0.9 else (0.0, 0.0, 1.0) if n[1] < -0.9 else (0.0, 1.0, 0.0)
    right = vcross((-n[0], -n[1], -n[2]), up)
    return right, up


class Batch:
    """Geometry of one mesh primitive (one material, with or without TANGENT)."""

    def __init__(self, tangents):
        self.pos = array.array("f")
        self.nrm = array.array("f")
        self.uv = array.array("f")
        self.tan = array.array("f") if tangents else None
        self.idx = array.array("I")
        self.count = 0

    def grid(self, ns, nt, verts):
        """verts: (ns+1)*(nt+1) tuples (p, n, uv, t) in s-major order; emits
        2*ns*nt triangles wound so that the geometric normal agrees with the
        vertex normals."""
        base = self.count
        pos, nrm, uv, tan = self.pos, self.nrm, self.uv, self.tan
        for p, n, t2, tg in verts:
            pos.extend(p)
            nrm.extend(n)
            uv.extend(t2)
            if tan is not None:
                tan.extend(tg)
        self.count += len(verts)
        # orientation from the first cell
        m = nt + 1
        a = verts[0][0]
        g = vcross(vsub(verts[m][0], a), vsub(verts[m + 1][0], a))
        if vdot(g, g) < 1e-20:
            g = vcross(vsub(verts[m + 1][0], a), vsub(verts[1][0], a))
        flip = vdot(g, verts[0][1]) < 0
        out = []
        for i in range(ns):
            r0 = base + i * m
            r1 = r0 + m
            for j in range(nt):
                v00, v10, v11, v01 = r0 + j, r1 + j, r1 + j + 1, r0 + j + 1
                if flip:
                    out += (v00, v11, v10, v00, v01, v11)
                else:
                    out += (v00, v10, v11, v00, v11, v01)
        self.idx.extend(out)

    def fan(self, centre, ring, n, uvfn, tg):
        """Disc: centre + ring points (closed loop), normal n."""
        base = self.count
        for p in [centre] + ring:
            self.pos.extend(p)
            self.nrm.extend(n)
            self.uv.extend(uvfn(p))
            if self.tan is not None:
                self.tan.extend(tg)
        self.count += 1 + len(ring)
        k = len(ring)
        g = vcross(vsub(ring[0], centre), vsub(ring[1], centre))
        flip = vdot(g, n) < 0
        out = []
        for i in range(k):
            a, b = base + 1 + i, base + 1 + (i + 1) % k
            out += (base, b, a) if flip else (base, a, b)
        self.idx.extend(out)


def plane_uv(p, right, up):
    return (vdot(p, right), -vdot(p, up))


def emit_plane(batch, o, a, b, n, ns, nt):
    """Rectangle o + s*a + t*b (s, t in [0, 1]) with outward normal n."""
    right, up = plane_frame(n)
    tg = right + (1.0,)
    verts = []
    for i in range(ns + 1):
        s = i / ns
        for j in range(nt + 1):
            t = j / nt
            p = (o[0] + s * a[0] + t * b[0], o[1] + s * a[1] + t * b[1], o[2] + s * a[2] + t * b[2])
            verts.append((p, n, plane_uv(p, right, up), tg))
    batch.grid(ns, nt, verts)


def cells(length, dens):
    return max(1, int(round(length * dens)))


# A "surface" is (kind, args, triangle count); kinds are emitted by emit().

def box(surfs, x0, x1, y0, y1, z0, z1, dens, skip=()):
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    faces = [
        ("-x", (x0, y0, z0), (0, dy, 0), (0, 0, dz), (-1.0, 0.0, 0.0), cells(dy, dens), cells(dz, dens)),
        ("+x", (x1, y0, z0), (0, dy, 0), (0, 0, dz), (1.0, 0.0, 0.0), cells(dy, dens), cells(dz, dens)),
        ("-y", (x0, y0, z0), (dx, 0, 0), (0, 0, dz), (0.0, -1.0, 0.0), cells(dx, dens), cells(dz, dens)),
        ("+y", (x0, y1, z0), (dx, 0, 0), (0, 0, dz), (0.0, 1.0, 0.0), cells(dx, dens), cells(dz, dens)),
        ("-z", (x0, y0, z0), (dx, 0, 0), (0, dy, 0), (0.0, 0.0, -1.0), cells(dx, dens), cells(dy, dens)),
        ("+z", (x0, y0, z1), (dx, 0, 0), (0, dy, 0), (0.0, 0.0, 1.0), cells(dx, dens), cells(dy, dens)),
    ]
    for name, o, a, b, n, ns, nt in faces:
        if name in skip:
            continue
        surfs.append(("plane", (o, a, b, n, ns, nt), 2 * ns * nt))


def cylinder(surfs, cx, cz, r, y0, y1, segs, rings, tangents):
    surfs.append(("cyl", (cx, cz, r, y0, y1, segs, rings, tangents), 2 * segs * rings))
    surfs.append(("disc", (cx, cz, r, y0, segs, -1.0), segs))
    surfs.append(("disc", (cx, cz, r, y1, segs, 1.0), segs))


def emit_cyl(batch, cx, cz, r, y0, y1, segs, rings, tangents):
    verts = []
    for i in range(segs + 1):
        a = 2 * math.pi * i / segs
        c, s = math.cos(a), math.sin(a)
        if i == segs:
            c, s = 1.0, 0.0
        n = (c, 0.0, s)
        tg = (s, 0.0, -c, 1.0)
        u = -r * a
        for j in range(rings + 1):
            y = y0 + (y1 - y0) * j / rings
            verts.append(((cx + r * c, y, cz + r * s), n, (u, -y), tg))
    batch.grid(segs, rings, verts)


def emit_disc(batch, cx, cz, r, y, segs, ny):
    ring = []
    for i in range(segs):
        a = 2 * math.pi * i / segs
        ring.append((cx + r * math.cos(a), y, cz + r * math.sin(a)))
    n = (0.0, ny, 0.0)
    right, up = plane_frame(n)
    batch.fan((cx, y, cz), ring, n, lambda p: plane_uv(p, right, up), right + (1.0,))


def arch_thetas(segs, hw, h):
    corner = math.atan2(h, hw)
    ts = [math.pi * k / segs for k in range(segs + 1)]
    ts = [t for t in ts if abs(t - corner) > 1e-3 and abs(t - (math.pi - corner)) > 1e-3]
    return sorted(ts + [corner, math.pi - corner])


def arch_block(surfs, xc, hw, r, ys, ytop, z0, z1, segs, radial, dens):
    """A bay's arch block: x in [xc-hw, xc+hw], y in [ys, ytop], z in [z0, z1]
    minus the half disc of radius r about (xc, ys): front/back faces, the
    semicircular intrados, top, ends and the two springing feet."""
    th = arch_thetas(segs, hw, ytop - ys)
    n = len(th) - 1
    nz = cells(z1 - z0, dens)
    surfs.append(("archface", (xc, hw, r, ys, ytop, z0, -1.0, th, radial), 2 * n * radial))
    surfs.append(("archface", (xc, hw, r, ys, ytop, z1, 1.0, th, radial), 2 * n * radial))
    surfs.append(("intrados", (xc, r, ys, z0, z1, th, nz), 2 * n * nz))
    x0, x1 = xc - hw, xc + hw
    ny, nzz = cells(ytop - ys, dens), nz
    surfs.append(("plane", ((x0, ytop, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0), (0.0, 1.0, 0.0),
                            cells(x1 - x0, dens), nzz), 2 * cells(x1 - x0, dens) * nzz))
    surfs.append(("plane", ((x0, ys, z0), (0, ytop - ys, 0), (0, 0, z1 - z0), (-1.0, 0.0, 0.0), ny, nzz), 2 * ny * nzz))
    surfs.append(("plane", ((x1, ys, z0), (0, ytop - ys, 0), (0, 0, z1 - z0), (1.0, 0.0, 0.0), ny, nzz), 2 * ny * nzz))
    foot = hw - r
    surfs.append(("plane", ((x0, ys, z0), (foot, 0, 0), (0, 0, z1 - z0), (0.0, -1.0, 0.0), 1, nzz), 2 * nzz))
    surfs.append(("plane", ((xc + r, ys, z0), (foot, 0, 0), (0, 0, z1 - z0), (0.0, -1.0, 0.0), 1, nzz), 2 * nzz))


def emit_archface(batch, xc, hw, r, ys, ytop, z, nzs, th, radial):
    n = (0.0, 0.0, nzs)
    right, up = plane_frame(n)
    h = ytop - ys
    verts = []
    for t in th:
        c, s = math.cos(t), math.sin(t)
        if abs(c) < 1e-12:
            c = 0.0
        d = h / s if s > 1e-12 else float("inf")
        if c != 0.0:
            d = min(d, hw / abs(c))
        p = (xc + r * c, ys + r * s)
        q = (xc + d * c, ys + d * s)
        for j in range(radial + 1):
            f = j / radial
            v = (p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1]), z)
            verts.append((v, n, plane_uv(v, right, up), None))
    batch.grid(len(th) - 1, radial, verts)


def emit_intrados(batch, xc, r, ys, z0, z1, th, nz):
    verts = []
    for t in th:
        c, s = math.cos(t), math.sin(t)
        n = (-c, -s, 0.0)
        for j in range(nz + 1):
            z = z0 + (z1 - z0) * j / nz
            verts.append(((xc + r * c, ys + r * s, z), n, (r * t, z), None))
    batch.grid(len(th) - 1, nz, verts)


def emit(batch, kind, args):
    if kind == "plane":
        emit_plane(batch, *args)
    elif kind == "cyl":
        emit_cyl(batch, *args)
    elif kind == "disc":
        emit_disc(batch, *args)
    elif kind == "archface":
        emit_archface(batch, *args)
    elif kind == "intrados":
        emit_intrados(batch, *args)
    else:
        raise ValueError(kind)


# material slots of the base set
WALL, ARCH, COLUMN, FLOOR, PLASTER, RAILING, FITTING, LAMP = range(8)


def build(f):
    """Surfaces for tessellation factor f: list of (group, tangents, kind,
    args, triangles). group: a base material slot, or ("stone", element
    index) for the arch blocks and column parts that take the stone
    variants."""
    out = []
    dens = 0.35 * f                       # plane cells per metre
    col_segs = max(12, int(round(20 * f)))
    col_rings = max(1, int(round(1.5 * f)))
    arch_segs = max(12, int(round(20 * f)))
    radial = max(1, int(round(1.5 * f)))
    bal_segs = max(6, int(round(6 * f)))

    def add(group, tangents, surfs):
        for kind, args, tris in surfs:
            out.append((group, tangents, kind, args, tris))

    element = 0
    for storey in range(2):
        y0 = storey * STOREY
        ys = y0 + SPRING
        ytop = y0 + STOREY
        for side in (-1.0, 1.0):
            zc = side * COURT_Z
            z0, z1 = zc - DEPTH / 2, zc + DEPTH / 2
            for k in range(BAYS + 1):
                x = -COURT_X + k * BAY_W
                s = []
                box(s, x - PLINTH, x + PLINTH, y0, y0 + 0.3, zc - PLINTH, zc + PLINTH, dens)
                add(("stone", element, False), False, s)
                element += 1
                s = []
                cylinder(s, x, zc, RING_R, y0 + 0.3, y0 + 0.5, col_segs, 1, True)
                cylinder(s, x, zc, SHAFT_R, y0 + 0.5, ys - 0.35, col_segs, col_rings, True)
                add(("stone", element, False), True, [(kd, a, t) for kd, a, t in s])
                element += 1
                s = []
                box(s, x - PIER / 2, x + PIER / 2, ys - 0.35, ys, z0, z1, dens)
                add(("stone", element, False), False, s)
                element += 1
            for k in range(BAYS):
                xc = -COURT_X + (k + 0.5) * BAY_W
                s = []
                arch_block(s, xc, BAY_W / 2, ARCH_R, ys, ytop, z0, z1, arch_segs, radial, dens)
                add(("stone", element, True), False, s)
                element += 1
                if storey == 1:
                    # railing between the upper columns, on the court side of the shafts
                    s = []
                    xa, xb = xc - BAY_W / 2 + SHAFT_R - 0.02, xc + BAY_W / 2 - SHAFT_R + 0.02
                    box(s, xa, xb, y0 + 1.0, y0 + 1.08, zc - 0.05, zc + 0.05, dens)
                    box(s, xa, xb, y0 + 0.1, y0 + 0.16, zc - 0.04, zc + 0.04, dens)
                    nb = int((xb - xa) / 0.2)
                    for b in range(1, nb):
                        bx = xa + b * (xb - xa) / nb
                        cylinder(s, bx, zc, 0.018, y0 + 0.16, y0 + 1.0, bal_segs, 1, False)
                    add(RAILING, False, s)
    # slabs: the upper gallery floor and the gallery roofs, plaster
    for side in (-1.0, 1.0):
        s = []
        za, zb = sorted((side * (COURT_Z + DEPTH / 2), side * GALLERY_Z))
        box(s, -COURT_X, COURT_X, STOREY - SLAB_T, STOREY, za, zb, dens)
        za2, zb2 = sorted((side * (COURT_Z + DEPTH / 2), side * (GALLERY_Z + WALL_T)))
        box(s, -COURT_X, COURT_X, HEIGHT - SLAB_T, HEIGHT, za2, zb2, dens)
        add(PLASTER, False, s)
    # walls: back walls of the galleries and the end walls of the court
    s = []
    for side in (-1.0, 1.0):
        za, zb = sorted((side * GALLERY_Z, side * (GALLERY_Z + WALL_T)))
        box(s, -COURT_X, COURT_X, 0.0, HEIGHT, za, zb, dens)
        xa, xb = sorted((side * COURT_X, side * (COURT_X + WALL_T)))
        box(s, xa, xb, 0.0, HEIGHT, -(GALLERY_Z + WALL_T), GALLERY_Z + WALL_T, dens)
    add(WALL, False, s)
    # floor: one box under the whole building, its top finely gridded
    s = []
    fd = max(dens, 0.5 * f)
    box(s, -COURT_X - WALL_T, COURT_X + WALL_T, -0.2, 0.0, -GALLERY_Z - WALL_T, GALLERY_Z + WALL_T, fd)
    add(FLOOR, False, s)
    # lamps on brackets on the court face of ground-floor piers 1 and 4
    for side in (-1.0, 1.0):
        for k in (1, BAYS - 1):
            x = -COURT_X + k * BAY_W
            zf = side * (COURT_Z - DEPTH / 2)     # court face of the capital line
            zo = side * (COURT_Z - DEPTH / 2 - 0.45)
            za, zb = sorted((zf + side * 0.02, zo))
            s = []
            box(s, x - 0.04, x + 0.04, 3.0, 3.08, za, zb, dens)            # arm
            box(s, x - 0.03, x + 0.03, 2.78, 3.0, zo - 0.03, zo + 0.03, dens)  # drop
            box(s, x - 0.16, x + 0.16, 2.74, 2.78, zo - 0.16, zo + 0.16, dens)  # cap
            add(FITTING, False, s)
            s = []
            box(s, x - 0.13, x + 0.13, 2.40, 2.74, zo - 0.13, zo + 0.13, dens)
            add(LAMP, False, s)
    return out, element


def choose_f(target):
    lo, hi = 0.05, 64.0
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        n = sum(s[4] for s in build(mid)[0])
        if n < target:
            lo = mid
        else:
            hi = mid
    nlo = sum(s[4] for s in build(lo)[0])
    nhi = sum(s[4] for s in build(hi)[0])
    return lo if abs(nlo - target) <= abs(nhi - target) else hi


# ---- materials ----------------------------------------------------------------

def quat_from_to(a, b):
    a, b = vnorm(a), vnorm(b)
    d = vdot(a, b)
    c = vcross(a, b)
    w = 1.0 + d
    q = (c[0], c[1], c[2], w)
    n = math.sqrt(sum(x * x for x in q))
    return [round(x / n, 9) for x in q]


def quat_mul(p, q):
    px, py, pz, pw = p
    qx, qy, qz, qw = q
    return [pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
            pw * qw - px * qx - py * qy - pz * qz]


def materials(m):
    T_STONE, T_STONE_N, T_FLOOR, T_PLASTER, T_METAL, T_LAMP = range(6)
    stone = lambda name, f: {
        "name": name,
        "pbrMetallicRoughness": {"baseColorTexture": {"index": T_STONE}, "baseColorFactor": f + [1.0],
                                 "metallicFactor": 0.0, "roughnessFactor": 0.85},
        "normalTexture": {"index": T_STONE_N, "scale": 1.0},
    }
    mats = [
        stone("wall_stone", [0.78, 0.74, 0.68]),
        stone("arch_stone", [0.92, 0.88, 0.8]),
        stone("column_stone", [0.88, 0.86, 0.84]),
        {"name": "floor_tiles",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": T_FLOOR, "extensions": {
             "KHR_texture_transform": {"scale": [0.5, 0.5]}}},
             "metallicFactor": 0.0, "roughnessFactor": 0.6}},
        {"name": "plaster",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": T_PLASTER}, "metallicFactor": 0.0,
                                  "roughnessFactor": 0.95}},
        {"name": "railing_iron",
         "pbrMetallicRoughness": {"baseColorFactor": [0.53, 0.51, 0.49, 1.0],
                                  "metallicRoughnessTexture": {"index": T_METAL},
                                  "metallicFactor": 1.0, "roughnessFactor": 1.0}},
        {"name": "lamp_brass",
         "pbrMetallicRoughness": {"baseColorFactor": [0.91, 0.78, 0.42, 1.0],
                                  "metallicRoughnessTexture": {"index": T_METAL},
                                  "metallicFactor": 1.0, "roughnessFactor": 0.8}},
        {"name": "lamp_glow",
         "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.85, 0.75, 1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 0.5},
         "emissiveTexture": {"index": T_LAMP},
         "emissiveFactor": [1.0, 1.0, 1.0],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12.0}}},
    ]
    for v in range(m - len(mats)):
        # deterministic tints of warm stone: brightness 0.6..1, ochre to grey
        bright = 0.6 + 0.4 * hash01(v, 0, 21)
        warm = hash01(v, 1, 21)
        tint = [round(bright * 0.95, 4), round(bright * (0.88 - 0.1 * warm), 4),
                round(bright * (0.82 - 0.25 * warm), 4)]
        mats.append(stone("stone_variant_%02d" % v, tint))
    textures = [
        {"name": "stone_color", "sampler": 0, "source": 0},
        {"name": "stone_normal", "sampler": 0, "source": 1},
        {"name": "floor_color", "sampler": 0, "source": 2},
        {"name": "plaster_color", "sampler": 1, "source": 3},
        {"name": "metal_mr", "sampler": 0, "source": 4},
        {"name": "lamp_emissive", "sampler": 2, "source": 5},
    ]
    samplers = [
        {"name": "repeat", "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497},
        {"name": "mirrored", "magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 33648},
        {"name": "clamp", "magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071},
    ]
    images = [("stone_color", make_stone_color), ("stone_normal", make_stone_normal),
              ("floor_color", make_floor_color), ("plaster_color", make_plaster_color),
              ("metal_mr", make_metal_mr), ("lamp_emissive", make_lamp_emissive)]
    return mats, textures, samplers, images


# ---- writing ------------------------------------------------------------------

def write_atomic(path, data):
    tmp = path + ".tmp%d" % os.getpid()
    with open(tmp, "wb") as fh:
        fh.write(data)
    os.replace(tmp, path)


def le_bytes(arr):
    if sys.byteorder != "little":
        arr = array.array(arr.typecode, arr)
        arr.byteswap()
    return arr.tobytes()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(HERE, "atrium"))
    ap.add_argument("--name", default="atrium")
    ap.add_argument("--triangles", type=int, default=30000)
    ap.add_argument("--materials", type=int, default=8)
    ap.add_argument("--glb", action="store_true")
    args = ap.parse_args()
    if args.materials < 8:
        ap.error("--materials must be at least 8")
    if args.triangles < 1000:
        ap.error("--triangles must be at least 1000")

    f = choose_f(args.triangles)
    surfs, n_elements = build(f)
    n_variants = args.materials - 8
    pool = [ARCH, COLUMN] + [8 + v for v in range(n_variants)]
    if n_elements < len(pool):
        ap.error("at most %d materials (%d stone elements)" % (8 + n_elements - 2, n_elements))

    # stone elements: arch blocks keep arch_stone, column parts column_stone,
    # unless variants spread over all of them round robin
    def material_of(group):
        if isinstance(group, tuple):
            e = group[1]
            if n_variants == 0:
                return ARCH if group[2] else COLUMN
            return pool[e % len(pool)]
        return group

    batches = {}
    order = []
    for group, tangents, kind, a, _ in surfs:
        key = (material_of(group), tangents)
        if key not in batches:
            batches[key] = Batch(tangents)
            order.append(key)
        emit(batches[key], kind, a)
    order.sort()

    mats, textures, samplers, images = materials(args.materials)
    names = ["wall", "arch", "column", "floor", "plaster", "railing", "lamp_fitting", "lamp"]

    chunks = []
    offset = 0
    views = []
    accessors = []

    def add_view(payload, target):
        nonlocal offset
        pad = (-offset) % 4
        if pad:
            chunks.append(b"\x00" * pad)
            offset += pad
        v = {"buffer": 0, "byteOffset": offset, "byteLength": len(payload)}
        if target:
            v["target"] = target
        views.append(v)
        chunks.append(payload)
        offset += len(payload)
        return len(views) - 1

    def add_accessor(arr, comps, type_, target, minmax=False, comp_type=5126):
        acc = {"bufferView": add_view(le_bytes(arr), target), "componentType": comp_type,
               "count": len(arr) // comps, "type": type_}
        if minmax:
            acc["min"] = [min(arr[i::comps]) for i in range(comps)]
            acc["max"] = [max(arr[i::comps]) for i in range(comps)]
        accessors.append(acc)
        return len(accessors) - 1

    meshes, nodes = [], []
    total_tris = 0
    used_materials = set()
    for key in order:
        b = batches[key]
        mat, tangents = key
        attrs = {"POSITION": add_accessor(b.pos, 3, "VEC3", 34962, True),
                 "NORMAL": add_accessor(b.nrm, 3, "VEC3", 34962),
                 "TEXCOORD_0": add_accessor(b.uv, 2, "VEC2", 34962)}
        if tangents:
            attrs["TANGENT"] = add_accessor(b.tan, 4, "VEC4", 34962)
        ind = add_accessor(b.idx, 1, "SCALAR", 34963, comp_type=5125)
        total_tris += len(b.idx) // 3
        used_materials.add(mat)
        mname = (names[mat] if mat < 8 else mats[mat]["name"]) + ("_tangents" if tangents else "")
        meshes.append({"name": mname, "primitives": [{"attributes": attrs, "indices": ind, "material": mat,
                                                      "mode": 4}]})
        nodes.append({"name": mname, "mesh": len(meshes) - 1})
    assert used_materials == set(range(len(mats))), "unused materials"

    # camera at the west end of the court looking east (+X), 8 deg up
    yaw = [0.0, math.sin(math.radians(-90) / 2), 0.0, math.cos(math.radians(-90) / 2)]
    pitch = [math.sin(math.radians(8) / 2), 0.0, 0.0, math.cos(math.radians(8) / 2)]
    cam_q = [round(x, 9) for x in quat_mul(yaw, pitch)]
    nodes.append({"name": "camera", "camera": 0, "translation": [-9.2, 1.7, 0.0], "rotation": cam_q})
    # sun: 65 deg elevation, from the south-west (-Z, -X), travelling to +Z +X
    el, az = math.radians(65), math.radians(20)
    travel = (math.cos(el) * math.sin(az), -math.sin(el), math.cos(el) * math.cos(az))
    nodes.append({"name": "sun", "rotation": quat_from_to((0.0, 0.0, -1.0), travel),
                  "extensions": {"KHR_lights_punctual": {"light": 0}}})

    image_bytes = [(nm, fn()) for nm, fn in images]
    stem = args.name
    gltf = {
        "asset": {"version": "2.0", "generator": "giharness make_atrium.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"],
        "scene": 0,
        "scenes": [{"name": stem, "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": mats,
        "textures": textures,
        "samplers": samplers,
        "cameras": [{"name": "camera", "type": "perspective",
                     "perspective": {"yfov": 1.0, "aspectRatio": 1.7777778, "znear": 0.05}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "color": [1.0, 0.95, 0.88], "intensity": 4.0,
             "extras": {"angular_radius": 0.00465}}]}},
    }
    os.makedirs(args.out, exist_ok=True)
    if args.glb:
        gltf["images"] = []
        for nm, data in image_bytes:
            gltf["images"].append({"name": nm, "mimeType": "image/png", "bufferView": add_view(data, None)})
        bin_data = b"".join(chunks)
        bin_data += b"\x00" * ((-len(bin_data)) % 4)
        gltf["buffers"] = [{"byteLength": len(bin_data)}]
        gltf["bufferViews"] = views
        gltf["accessors"] = accessors
        js = json.dumps(gltf, separators=(",", ":")).encode()
        js += b" " * ((-len(js)) % 4)
        total = 12 + 8 + len(js) + 8 + len(bin_data)
        glb = (struct.pack("<III", 0x46546C67, 2, total) + struct.pack("<II", len(js), 0x4E4F534A) + js +
               struct.pack("<II", len(bin_data), 0x004E4942) + bin_data)
        path = os.path.join(args.out, stem + ".glb")
        write_atomic(path, glb)
        written = [path]
    else:
        written = []
        gltf["images"] = []
        for nm, data in image_bytes:
            fname = "%s_%s.png" % (stem, nm)
            p = os.path.join(args.out, fname)
            write_atomic(p, data)
            written.append(p)
            gltf["images"].append({"name": nm, "uri": fname})
        bin_data = b"".join(chunks)
        p = os.path.join(args.out, stem + ".bin")
        write_atomic(p, bin_data)
        written.append(p)
        gltf["buffers"] = [{"uri": stem + ".bin", "byteLength": len(bin_data)}]
        gltf["bufferViews"] = views
        gltf["accessors"] = accessors
        path = os.path.join(args.out, stem + ".gltf")
        write_atomic(path, (json.dumps(gltf, indent=1) + "\n").encode())
        written.append(path)
    size = sum(os.path.getsize(p) for p in written)
    if abs(total_tris - args.triangles) > 0.1 * args.triangles:
        print("warning: %d triangles, more than 10 %% off the target %d (the coarsest tessellation has ~9000)" %
              (total_tris, args.triangles), file=sys.stderr)
    print("%s: %d triangles, %d materials, %d meshes, %d bytes in %d file(s) (tessellation factor %.3f)" %
          (path, total_tris, len(mats), len(meshes), size, len(written), f))


if __name__ == "__main__":
    main()
