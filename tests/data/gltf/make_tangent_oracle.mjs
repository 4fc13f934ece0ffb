// Writes tests/data/gltf/tangent_oracle.gltf: reference MikkTSpace tangents for
// tests/tangents_test.cpp, computed by the npm package `mikktspace`
// (Don McCurdy's WebAssembly build of gltf-rs/mikktspace, the port of Morten
// Mikkelsen's mikktspace.c that glTF-Transform uses).
//
// Re-run (the package is installed outside the repository):
//   mkdir -p /tmp/tangent_work && (cd /tmp/tangent_work && npm init -y && npm install mikktspace@1.1.1)
//   MIKKTSPACE_PREFIX=/tmp/tangent_work node tests/data/gltf/make_tangent_oracle.mjs
// (from the repository root; the output is deterministic, so an unchanged
// package rewrites the same file).
//
// What the file holds, per mesh (one node each):
//  - one primitive, UNWELDED: every face corner is its own vertex (MikkTSpace's
//    input), with POSITION, NORMAL, TEXCOORD_0, TANGENT (the oracle) and the
//    trivial indices 0..n-1, so the file stays an ordinary indexed glTF;
//  - primitive.extras.weldedIndices: an accessor (SCALAR UNSIGNED_INT, one per
//    corner) naming each corner's vertex after welding by exact equality of
//    position, normal and uv, vertices numbered in order of first use. The
//    test rebuilds the welded mesh from it and feeds that to gi::generate_tangents,
//    then compares corner by corner with TANGENT (welding may merge corners
//    whose oracle tangents differ, which is why the oracle stays unwelded).
//
// Sign convention: MikkTSpace's bitangent points along +v. glTF's v runs down
// the image while its normal maps' green points up, so glTF tools store
// w = -sign (glTF-Transform's tangents(); KhronosGroup/glTF-Sample-Models#174).
// TANGENT here is in glTF convention: w already negated.
import { createRequire } from 'node:module';
import { writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const prefix = process.env.MIKKTSPACE_PREFIX ?? '/tmp/tangent_work';
const { generateTangents } = createRequire(join(prefix, 'package.json'))('mikktspace');

// ---------------------------------------------------------------------------
// Meshes, built indexed (vertices + triangle list) and then unwelded.

function indexedMesh() {
  return { positions: [], normals: [], uvs: [], triangles: [] };
}

function addVertex(mesh, p, n, uv) {
  mesh.positions.push(p);
  mesh.normals.push(n);
  mesh.uvs.push(uv);
  return mesh.positions.length - 1;
}

function normalize([x, y, z]) {
  const l = Math.hypot(x, y, z);
  return [x / l, y / l, z / l];
}

// A UV sphere: a seam where u wraps (u = 0 and u = 1 share positions) and
// poles where every segment has its own pole vertex (one position, many uvs).
function uvSphere(segments, rings) {
  const m = indexedMesh();
  const grid = [];
  for (let r = 0; r <= rings; ++r) {
    const row = [];
    const theta = (Math.PI * r) / rings;
    for (let s = 0; s <= segments; ++s) {
      const atPole = r === 0 || r === rings;
      const u = atPole ? (s + 0.5) / segments : s / segments;
      const phi = 2 * Math.PI * u;
      const p = atPole ? [0, Math.cos(theta), 0]
                       : [Math.sin(theta) * Math.cos(phi), Math.cos(theta), -Math.sin(theta) * Math.sin(phi)];
      row.push(addVertex(m, p, normalize(p), [u, r / rings]));
    }
    grid.push(row);
  }
  for (let r = 0; r < rings; ++r) {
    for (let s = 0; s < segments; ++s) {
      const a = grid[r][s], b = grid[r + 1][s], c = grid[r + 1][s + 1], d = grid[r][s + 1];
      if (r !== 0) m.triangles.push([a, b, d]);
      if (r !== rings - 1) m.triangles.push([d, b, c]);
    }
  }
  return m;
}

// A capped cylinder: a side with a u seam, and flat caps whose rim vertices
// share positions with the side but not normals.
function cylinder(segments, radius, height) {
  const m = indexedMesh();
  const side = [];
  for (let s = 0; s <= segments; ++s) {
    const u = s / segments, phi = 2 * Math.PI * u;
    const x = radius * Math.cos(phi), z = -radius * Math.sin(phi);
    const n = [Math.cos(phi), 0, -Math.sin(phi)];
    side.push([addVertex(m, [x, height, z], n, [u, 0]), addVertex(m, [x, 0, z], n, [u, 1])]);
  }
  for (let s = 0; s < segments; ++s) {
    const [t0, b0] = side[s], [t1, b1] = side[s + 1];
    m.triangles.push([t0, b0, t1], [t1, b0, b1]);
  }
  for (const [y, ny] of [[height, 1], [0, -1]]) {
    const centre = addVertex(m, [0, y, 0], [0, ny, 0], [0.5, 0.5]);
    const rim = [];
    for (let s = 0; s < segments; ++s) {
      const phi = (2 * Math.PI * s) / segments;
      const x = radius * Math.cos(phi), z = -radius * Math.sin(phi);
      rim.push(addVertex(m, [x, y, z], [0, ny, 0], [0.5 + 0.5 * Math.cos(phi), 0.5 + 0.5 * Math.sin(phi)]));
    }
    for (let s = 0; s < segments; ++s) {
      const a = rim[s], b = rim[(s + 1) % segments];
      m.triangles.push(ny > 0 ? [centre, a, b] : [centre, b, a]);
    }
  }
  return m;
}

// A quad whose two triangles have opposite uv winding: the uvs are mirrored
// across the shared diagonal, so the diagonal's vertices are shared (same
// position, normal, uv) by triangles of both orientations. A degenerate
// triangle on the diagonal follows: its corners must copy the first good
// triangle's frames there (the uv-preserving one's), not the mirrored one's.
function mirroredQuad() {
  const m = indexedMesh();
  const n = [0, 0, 1];
  const v0 = addVertex(m, [0, 0, 0], n, [0, 0]);
  const v1 = addVertex(m, [1, 0, 0], n, [1, 0]);
  const v2 = addVertex(m, [1, 1, 0], n, [1, 1]);
  const v3 = addVertex(m, [0, 1, 0], n, [1, 0]);
  m.triangles.push([v0, v1, v2], [v0, v2, v3], [v2, v0, v0]);
  return m;
}

// A strip mirrored in u at x = 1, as an artist mirrors half a model onto the
// same texture: the middle column is shared by both orientations.
function mirroredStrip() {
  const m = indexedMesh();
  const n = [0, 0, 1];
  const id = [];
  for (let x = 0; x <= 2; ++x) {
    id.push([0, 1].map((y) => addVertex(m, [x, y, 0], n, [x <= 1 ? x : 2 - x, 1 - y])));
  }
  for (let x = 0; x < 2; ++x) {
    m.triangles.push([id[x][0], id[x + 1][0], id[x + 1][1]], [id[x][0], id[x + 1][1], id[x][1]]);
  }
  return m;
}

// A gently curved plane (height field) with rotated and sheared uvs: tangents
// differ from both the x axis and the triangle edges, and the varying normals
// make the projection onto each corner's tangent plane matter.
function skewedPlane(cells) {
  const m = indexedMesh();
  const angle = (35 * Math.PI) / 180, shear = 0.4;
  const id = [];
  for (let j = 0; j <= cells; ++j) {
    const row = [];
    for (let i = 0; i <= cells; ++i) {
      const x = i / cells, y = j / cells;
      const z = 0.15 * Math.sin(3 * x) * Math.cos(2 * y);
      const n = normalize([-0.45 * Math.cos(3 * x) * Math.cos(2 * y), 0.3 * Math.sin(3 * x) * Math.sin(2 * y), 1]);
      const sx = x + shear * y;
      const u = Math.cos(angle) * sx - Math.sin(angle) * y;
      const v = Math.sin(angle) * sx + Math.cos(angle) * y;
      row.push(addVertex(m, [x, y, z], n, [u, 1 - v]));
    }
    id.push(row);
  }
  for (let j = 0; j < cells; ++j) {
    for (let i = 0; i < cells; ++i) {
      const a = id[j][i], b = id[j][i + 1], c = id[j + 1][i + 1], d = id[j + 1][i];
      m.triangles.push([a, b, c], [a, c, d]);
    }
  }
  return m;
}

// A grid with the kinds of degeneracy MikkTSpace handles:
//  - a row of triangles with zero uv area (rows 1 and 2 share u), which
//    MikkTSpace lets join any neighbouring group ("group with any"), taking
//    that group's orientation;
//  - triangles with two identical corners (same position, normal and uv), which
//    it sets aside and whose corners copy the tangent of a good triangle's
//    corner at the same vertex; one sits mid-list, one at the end;
//  - a lone degenerate triangle with no good triangle at its vertices, which
//    keeps MikkTSpace's initial frame (tangent +x, here orthogonal to +z).
// u runs along y and v against x, so the tangents (+y) and signs (w = -1,
// orientation preserving) differ from that initial frame's (+x, w = +1).
function degenerateGrid(cells) {
  const m = indexedMesh();
  const n = [0, 0, 1];
  const uOfRow = (j) => (j <= 1 ? j : j - 1) / (cells - 1);
  const id = [];
  for (let j = 0; j <= cells; ++j) {
    id.push([...Array(cells + 1).keys()].map((i) => addVertex(m, [i / cells, j / cells, 0], n, [uOfRow(j), 1 - i / cells])));
  }
  for (let j = 0; j < cells; ++j) {
    for (let i = 0; i < cells; ++i) {
      const a = id[j][i], b = id[j][i + 1], c = id[j + 1][i + 1], d = id[j + 1][i];
      m.triangles.push([a, b, c], [a, c, d]);
      if (j === 0 && i === 1) m.triangles.push([b, b, c]);
    }
  }
  m.triangles.push([id[cells][0], id[cells][1], id[cells][0]]);
  const lone = [[2, 0, 0], [2, 1, 0]].map((p, k) => addVertex(m, p, n, [0.25, 0.25 * k]));
  m.triangles.push([lone[0], lone[1], lone[1]]);
  return m;
}

// ---------------------------------------------------------------------------
// Unweld, run the oracle, weld back.

function unweld(mesh) {
  const corners = mesh.triangles.flat();
  const pick = (attr, width) => Float32Array.from(corners.flatMap((v) => attr[v].slice(0, width)));
  return {
    position: pick(mesh.positions, 3),
    normal: pick(mesh.normals, 3),
    texcoord: pick(mesh.uvs, 2),
  };
}

// Each corner's welded vertex: exact equality of the float32 position, normal
// and uv (as mikktspace.c welds; String(-0) === '0', so -0 equals 0 as in C).
function weldedIndices({ position, normal, texcoord }) {
  const firstUse = new Map();
  const count = position.length / 3;
  const out = new Uint32Array(count);
  for (let c = 0; c < count; ++c) {
    const key = [...position.subarray(3 * c, 3 * c + 3), ...normal.subarray(3 * c, 3 * c + 3),
                 ...texcoord.subarray(2 * c, 2 * c + 2)].map(String).join(',');
    if (!firstUse.has(key)) firstUse.set(key, firstUse.size);
    out[c] = firstUse.get(key);
  }
  return out;
}

function oracleTangents(soup) {
  const tangent = generateTangents(soup.position, soup.normal, soup.texcoord);
  for (let i = 3; i < tangent.length; i += 4) tangent[i] = -tangent[i];  // glTF's v points down
  return tangent;
}

// ---------------------------------------------------------------------------
// glTF writer: one buffer, one bufferView per accessor.

class GltfBuilder {
  constructor() {
    this.chunks = [];
    this.byteLength = 0;
    this.json = {
      asset: { version: '2.0', generator: 'giharness tests/data/gltf/make_tangent_oracle.mjs' },
      scene: 0,
      scenes: [{ name: 'tangent_oracle', nodes: [] }],
      nodes: [], meshes: [], accessors: [], bufferViews: [], buffers: [],
    };
  }

  accessor(array, type, target, withBounds) {
    const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
    this.json.bufferViews.push({ buffer: 0, byteOffset: this.byteLength, byteLength: bytes.length, target });
    this.chunks.push(bytes);
    this.byteLength += bytes.length;  // every element is 4 bytes: views stay aligned
    const width = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[type];
    const accessor = {
      bufferView: this.json.bufferViews.length - 1,
      componentType: array instanceof Float32Array ? 5126 : 5125,
      count: array.length / width,
      type,
    };
    if (withBounds) {
      accessor.min = [...Array(width).keys()].map((k) => Math.min(...array.filter((_, i) => i % width === k)));
      accessor.max = [...Array(width).keys()].map((k) => Math.max(...array.filter((_, i) => i % width === k)));
    }
    this.json.accessors.push(accessor);
    return this.json.accessors.length - 1;
  }

  addMesh(name, soup, tangent, welded) {
    const ARRAY_BUFFER = 34962, ELEMENT_ARRAY_BUFFER = 34963;
    const corners = soup.position.length / 3;
    const primitive = {
      attributes: {
        POSITION: this.accessor(soup.position, 'VEC3', ARRAY_BUFFER, true),
        NORMAL: this.accessor(soup.normal, 'VEC3', ARRAY_BUFFER),
        TEXCOORD_0: this.accessor(soup.texcoord, 'VEC2', ARRAY_BUFFER),
        TANGENT: this.accessor(tangent, 'VEC4', ARRAY_BUFFER),
      },
      indices: this.accessor(Uint32Array.from({ length: corners }, (_, i) => i), 'SCALAR', ELEMENT_ARRAY_BUFFER),
      mode: 4,
    };
    primitive.extras = { weldedIndices: this.accessor(welded, 'SCALAR') };
    delete this.json.bufferViews[this.json.accessors[primitive.extras.weldedIndices].bufferView].target;
    this.json.meshes.push({ name, primitives: [primitive] });
    this.json.nodes.push({ name, mesh: this.json.meshes.length - 1 });
    this.json.scenes[0].nodes.push(this.json.nodes.length - 1);
  }

  toJson() {
    const all = Buffer.concat(this.chunks.map((c) => Buffer.from(c)));
    this.json.buffers.push({ byteLength: all.length, uri: `data:application/octet-stream;base64,${all.toString('base64')}` });
    return JSON.stringify(this.json, null, 1) + '\n';
  }
}

const meshes = {
  uv_sphere: uvSphere(8, 6),
  cylinder: cylinder(8, 0.5, 1.5),
  mirrored_quad: mirroredQuad(),
  mirrored_strip: mirroredStrip(),
  skewed_plane: skewedPlane(4),
  degenerate_grid: degenerateGrid(3),
};

const gltf = new GltfBuilder();
for (const [name, mesh] of Object.entries(meshes)) {
  const soup = unweld(mesh);
  gltf.addMesh(name, soup, oracleTangents(soup), weldedIndices(soup));
}
const out = join(dirname(fileURLToPath(import.meta.url)), 'tangent_oracle.gltf');
writeFileSync(out, gltf.toJson());
console.log(`wrote ${out}`);
