// MikkTSpace tangents (core/tangents.h) against the original:
// tests/data/gltf/tangent_oracle.gltf holds, per mesh, the unwelded corners
// with the tangents the reference implementation gave them (npm `mikktspace`,
// made by tests/data/gltf/make_tangent_oracle.mjs) and each corner's vertex
// after welding. The welded mesh goes through our generator and every corner
// must come out as the oracle's. The file is read here with nlohmann::json
// alone, so a change to the glTF importer cannot move these tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scene.h"
#include "core/tangents.h"

namespace {

using nlohmann::json;

// ---------------------------------------------------------------------------
// The oracle file.

std::vector<std::uint8_t> decode_base64(const std::string& text) {
  std::vector<std::uint8_t> bytes;
  std::uint32_t bits = 0;
  int bit_count = 0;
  for (const char c : text) {
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(alphabet, c);
    if (c == '=' || c == '\0' || at == nullptr) break;
    bits = (bits << 6) | std::uint32_t(at - alphabet);
    bit_count += 6;
    if (bit_count >= 8) {
      bit_count -= 8;
      bytes.push_back(std::uint8_t(bits >> bit_count));
    }
  }
  return bytes;
}

struct OracleFile {
  json gltf;
  std::vector<std::uint8_t> buffer;

  template <typename T>
  std::vector<T> read(int accessor_index, int width) const {
    const json& accessor = gltf["accessors"][accessor_index];
    const json& view = gltf["bufferViews"][accessor["bufferView"].get<int>()];
    const std::size_t offset = view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
    const std::size_t count = accessor["count"].get<std::size_t>() * width;
    std::vector<T> values(count);
    std::memcpy(values.data(), buffer.data() + offset, count * sizeof(T));
    return values;
  }
};

const OracleFile& oracle_file() {
  static const OracleFile file = [] {
    std::ifstream in(std::string(GIHARNESS_SOURCE_DIR) + "/tests/data/gltf/tangent_oracle.gltf");
    if (!in) throw std::runtime_error("tests/data/gltf/tangent_oracle.gltf is missing");
    OracleFile f;
    f.gltf = json::parse(in);
    const std::string uri = f.gltf["buffers"][0]["uri"];
    f.buffer = decode_base64(uri.substr(uri.find(',') + 1));
    return f;
  }();
  return file;
}

struct OracleMesh {
  std::string name;
  gi::Mesh welded;                 // what the generator is fed
  gi::Mesh unwelded;               // every corner its own vertex, as the oracle saw it
  std::vector<glm::vec4> tangent;  // the oracle's, per corner
};

template <typename Vec>
std::vector<Vec> as_vectors(const std::vector<float>& flat) {
  std::vector<Vec> out(flat.size() / Vec::length());
  std::memcpy(out.data(), flat.data(), flat.size() * sizeof(float));
  return out;
}

OracleMesh load_mesh(const json& mesh_json) {
  const OracleFile& file = oracle_file();
  const json& primitive = mesh_json["primitives"][0];
  const json& attributes = primitive["attributes"];
  OracleMesh m;
  m.name = mesh_json["name"];
  m.unwelded.name = m.name;
  m.unwelded.positions = as_vectors<glm::vec3>(file.read<float>(attributes["POSITION"], 3));
  m.unwelded.normals = as_vectors<glm::vec3>(file.read<float>(attributes["NORMAL"], 3));
  m.unwelded.uvs = as_vectors<glm::vec2>(file.read<float>(attributes["TEXCOORD_0"], 2));
  m.unwelded.indices = file.read<std::uint32_t>(primitive["indices"], 1);
  m.tangent = as_vectors<glm::vec4>(file.read<float>(attributes["TANGENT"], 4));

  // The welded mesh: vertex w takes the attributes of any corner welded to it
  // (all such corners are equal by construction).
  const std::vector<std::uint32_t> welded = file.read<std::uint32_t>(primitive["extras"]["weldedIndices"], 1);
  const std::size_t vertex_count = *std::max_element(welded.begin(), welded.end()) + 1;
  m.welded.name = m.name;
  m.welded.positions.resize(vertex_count);
  m.welded.normals.resize(vertex_count);
  m.welded.uvs.resize(vertex_count);
  for (std::size_t c = 0; c < welded.size(); ++c) {
    const std::uint32_t corner_vertex = m.unwelded.indices[c];
    m.welded.positions[welded[c]] = m.unwelded.positions[corner_vertex];
    m.welded.normals[welded[c]] = m.unwelded.normals[corner_vertex];
    m.welded.uvs[welded[c]] = m.unwelded.uvs[corner_vertex];
  }
  m.welded.indices = welded;
  return m;
}

const std::vector<OracleMesh>& oracle_meshes() {
  static const std::vector<OracleMesh> meshes = [] {
    std::vector<OracleMesh> out;
    for (const json& mesh_json : oracle_file().gltf["meshes"]) out.push_back(load_mesh(mesh_json));
    return out;
  }();
  return meshes;
}

const OracleMesh& oracle_mesh(const std::string& name) {
  for (const OracleMesh& m : oracle_meshes())
    if (m.name == name) return m;
  throw std::runtime_error("no mesh " + name + " in tangent_oracle.gltf");
}

// ---------------------------------------------------------------------------
// Comparisons.

float direction_difference(const glm::vec4& a, const glm::vec4& b) {
  return glm::length(glm::normalize(glm::vec3(a)) - glm::normalize(glm::vec3(b)));
}

constexpr float kDirectionTolerance = 1e-3f;

// Every corner's tangent against the oracle's; returns the largest direction
// difference (printed: the report of how close we are, mesh by mesh).
float expect_matches_oracle(const OracleMesh& m, const std::vector<glm::vec4>& tangent_of_corner) {
  float largest = 0.0f;
  for (std::size_t c = 0; c < m.tangent.size(); ++c) {
    const float difference = direction_difference(tangent_of_corner[c], m.tangent[c]);
    largest = std::max(largest, difference);
    EXPECT_LE(difference, kDirectionTolerance) << m.name << " corner " << c;
    EXPECT_EQ(tangent_of_corner[c].w, m.tangent[c].w) << m.name << " corner " << c << " (bitangent sign)";
  }
  return largest;
}

bool bitwise_equal(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)) == 0;
}

// ---------------------------------------------------------------------------

TEST(MikkTSpaceTangents, OracleFileHoldsEveryMeshItExercises) {
  std::set<std::string> names;
  for (const OracleMesh& m : oracle_meshes()) {
    names.insert(m.name);
    EXPECT_EQ(m.tangent.size(), m.welded.indices.size()) << m.name;
    EXPECT_LT(m.welded.positions.size(), m.unwelded.positions.size()) << m.name << " should weld";
  }
  EXPECT_EQ(names, (std::set<std::string>{"uv_sphere", "cylinder", "mirrored_quad", "mirrored_strip", "skewed_plane",
                                          "degenerate_grid"}));
}

TEST(MikkTSpaceTangents, CornerTangentsMatchTheReferenceImplementation) {
  for (const OracleMesh& m : oracle_meshes()) {
    const float largest = expect_matches_oracle(m, gi::mikktspace_corner_tangents(m.welded));
    std::cout << "[ oracle   ] " << m.name << ": " << m.tangent.size()
              << " corners, largest tangent difference " << largest << "\n";
  }
}

// The generator welds corners itself, as mikktspace.c does: the unwelded
// soup the oracle saw gives the very same corner tangents.
TEST(MikkTSpaceTangents, InputVertexSharingDoesNotChangeTheResult) {
  for (const OracleMesh& m : oracle_meshes())
    EXPECT_TRUE(bitwise_equal(gi::mikktspace_corner_tangents(m.unwelded), gi::mikktspace_corner_tangents(m.welded)))
        << m.name;
}

// Per-vertex tangents after splitting: each corner's vertex carries the
// oracle's tangent for that corner, and the rest of the vertex is unchanged.
TEST(MikkTSpaceTangents, PerVertexTangentsMatchTheReferenceAfterSplitting) {
  for (const OracleMesh& m : oracle_meshes()) {
    gi::Mesh mesh = m.welded;
    gi::generate_tangents(mesh);
    ASSERT_EQ(mesh.tangents.size(), mesh.positions.size()) << m.name;
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size()) << m.name;
    ASSERT_EQ(mesh.uvs.size(), mesh.positions.size()) << m.name;
    std::vector<glm::vec4> tangent_of_corner;
    for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
      const std::uint32_t before = m.welded.indices[c], after = mesh.indices[c];
      EXPECT_EQ(mesh.positions[after], m.welded.positions[before]) << m.name << " corner " << c;
      EXPECT_EQ(mesh.normals[after], m.welded.normals[before]) << m.name << " corner " << c;
      EXPECT_EQ(mesh.uvs[after], m.welded.uvs[before]) << m.name << " corner " << c;
      tangent_of_corner.push_back(mesh.tangents[after]);
    }
    expect_matches_oracle(m, tangent_of_corner);
  }
}

TEST(MikkTSpaceTangents, TangentsAreUnitAndOrthogonalToTheNormal) {
  for (const OracleMesh& m : oracle_meshes()) {
    gi::Mesh mesh = m.welded;
    gi::generate_tangents(mesh);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec3 t(mesh.tangents[v]);
      EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f) << m.name << " vertex " << v;
      EXPECT_NEAR(glm::dot(t, glm::normalize(mesh.normals[v])), 0.0f, 1e-5f) << m.name << " vertex " << v;
      EXPECT_TRUE(mesh.tangents[v].w == 1.0f || mesh.tangents[v].w == -1.0f) << m.name << " vertex " << v;
    }
  }
}

// The strip is mirrored in u at x = 1 and its middle column is shared by
// both halves (same position, normal and uv): those two vertices, and only
// they, are split. The halves' frames follow glTF's convention: v runs down
// (uv = (x, 1 - y) on the left), so the bitangent cross(n, t) * w must point
// up the strip (+y) on both sides.
TEST(MikkTSpaceTangents, AMirrorSeamSplitsExactlyItsVertices) {
  const OracleMesh& m = oracle_mesh("mirrored_strip");
  gi::Mesh mesh = m.welded;
  gi::generate_tangents(mesh);
  EXPECT_EQ(m.welded.positions.size(), 6u);
  EXPECT_EQ(mesh.positions.size(), m.welded.positions.size() + 2);
  for (std::size_t v = m.welded.positions.size(); v < mesh.positions.size(); ++v)
    EXPECT_FLOAT_EQ(mesh.positions[v].x, 1.0f) << "split vertex " << v << " is not on the seam";
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    const glm::vec4 t = mesh.tangents[mesh.indices[c]];
    const glm::vec3 bitangent = glm::cross(mesh.normals[mesh.indices[c]], glm::vec3(t)) * t.w;
    const bool left_half = c < 6;  // the first two triangles
    EXPECT_NEAR(t.x, left_half ? 1.0f : -1.0f, 1e-6f) << "corner " << c;
    EXPECT_NEAR(bitangent.y, 1.0f, 1e-6f) << "corner " << c;
  }
}

// The sphere's u seam and poles are already separate vertices (their uvs
// differ), so nothing there needs splitting.
TEST(MikkTSpaceTangents, AUvSeamWithSeparateVerticesSplitsNothing) {
  const OracleMesh& m = oracle_mesh("uv_sphere");
  gi::Mesh mesh = m.welded;
  gi::generate_tangents(mesh);
  EXPECT_EQ(mesh.positions.size(), m.welded.positions.size());
  EXPECT_EQ(mesh.indices, m.welded.indices);
}

// The quad's diagonal vertices are shared by a uv-preserving and a mirrored
// triangle: both split, with opposite bitangent signs. (The degenerate third
// triangle reuses the first triangle's frames, so it splits nothing more.)
TEST(MikkTSpaceTangents, MirroredTrianglesSplitTheirSharedVertices) {
  const OracleMesh& m = oracle_mesh("mirrored_quad");
  gi::Mesh mesh = m.welded;
  gi::generate_tangents(mesh);
  EXPECT_EQ(m.welded.positions.size(), 4u);
  EXPECT_EQ(mesh.positions.size(), 6u);
  EXPECT_EQ(mesh.tangents[mesh.indices[0]].w, -mesh.tangents[mesh.indices[3]].w);
}

TEST(MikkTSpaceTangents, OutputIsDeterministic) {
  for (const OracleMesh& m : oracle_meshes()) {
    EXPECT_TRUE(bitwise_equal(gi::mikktspace_corner_tangents(m.welded), gi::mikktspace_corner_tangents(m.welded)))
        << m.name;
    gi::Mesh first = m.welded, second = m.welded;
    gi::generate_tangents(first);
    gi::generate_tangents(second);
    EXPECT_TRUE(bitwise_equal(first.tangents, second.tangents)) << m.name;
    EXPECT_EQ(first.indices, second.indices) << m.name;
    EXPECT_EQ(first.positions, second.positions) << m.name;
  }
}

// Renumbering the vertices (here: reversing them) leaves every corner's
// tangent bit for bit as it was.
TEST(MikkTSpaceTangents, VertexOrderDoesNotChangeCornerTangents) {
  for (const OracleMesh& m : oracle_meshes()) {
    gi::Mesh reversed = m.welded;
    const std::uint32_t last = std::uint32_t(reversed.positions.size() - 1);
    std::reverse(reversed.positions.begin(), reversed.positions.end());
    std::reverse(reversed.normals.begin(), reversed.normals.end());
    std::reverse(reversed.uvs.begin(), reversed.uvs.end());
    for (std::uint32_t& index : reversed.indices) index = last - index;
    EXPECT_TRUE(bitwise_equal(gi::mikktspace_corner_tangents(reversed), gi::mikktspace_corner_tangents(m.welded)))
        << m.name;
  }
}

TEST(MikkTSpaceTangents, RejectsMeshesWithoutUvsOrNormals) {
  const gi::Mesh& quad = oracle_mesh("mirrored_quad").welded;
  gi::Mesh no_uvs = quad;
  no_uvs.uvs.clear();
  EXPECT_THROW(gi::generate_tangents(no_uvs), std::invalid_argument);
  EXPECT_THROW(gi::mikktspace_corner_tangents(no_uvs), std::invalid_argument);
  EXPECT_TRUE(no_uvs.tangents.empty());

  gi::Mesh no_normals = quad;
  no_normals.normals.clear();
  EXPECT_THROW(gi::generate_tangents(no_normals), std::invalid_argument);

  gi::Mesh bad_index = quad;
  bad_index.indices.back() = 99;
  EXPECT_THROW(gi::generate_tangents(bad_index), std::invalid_argument);

  gi::Mesh partial_triangle = quad;
  partial_triangle.indices.pop_back();
  EXPECT_THROW(gi::generate_tangents(partial_triangle), std::invalid_argument);
}

}  // namespace
