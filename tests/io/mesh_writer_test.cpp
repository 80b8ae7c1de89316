// write_mesh: posed frames written as OBJ and PLY, with and without posed normals, are parsed back
// by small independent readers and compared; invalid input throws and leaves nothing behind.

#include "cgamesh/io/mesh_writer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cgamesh::InvalidInputError;
using cgamesh::io::write_mesh;
using cgamesh::mesh::Mesh;
using cgamesh::mesh::RowMatrixXf;

using cgamesh_test::TempDir;

struct Frame {
  std::vector<Mesh> meshes;
  std::vector<RowMatrixXf<3>> posed;
  std::vector<RowMatrixXf<3>> normals;  ///< posed normals, one set per mesh
};

/// Two meshes: a tetrahedron with texture coordinates ("tet one", a name with a space) and a
/// quad without; posed positions differ from the rest positions and have awkward digits, and so
/// do the posed unit normals (which differ from the meshes' rest normals).
Frame make_frame() {
  Frame fr;
  Mesh tet;
  tet.name = "tet one";
  tet.positions.resize(4, 3);
  tet.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  tet.uvs.resize(4, 2);
  tet.uvs << 0, 0, 1, 0, 0, 1, 0.333333343f, 0.1f;
  tet.normals = tet.positions;  // rest normals: not written
  tet.faces.resize(4, 3);
  tet.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  Mesh quad;
  quad.positions.resize(4, 3);
  quad.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  quad.faces.resize(2, 3);
  quad.faces << 0, 1, 2, 0, 2, 3;
  fr.meshes = {tet, quad};
  for (const Mesh& m : fr.meshes) {
    RowMatrixXf<3> p = m.positions;
    for (Eigen::Index v = 0; v < p.rows(); ++v)
      p.row(v) =
          p.row(v) * 1.1f + Eigen::RowVector3f(0.1f, -2.5e-7f, 12345.678f) + Eigen::RowVector3f::Constant(float(v) / 3);
    fr.posed.push_back(p);
    RowMatrixXf<3> n(m.vertex_count(), 3);
    for (Eigen::Index v = 0; v < n.rows(); ++v)
      n.row(v) = Eigen::RowVector3f(float(v) + 1, -0.3f * float(v), 0.7f + 0.1f * float(fr.posed.size())).normalized();
    fr.normals.push_back(n);
  }
  return fr;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ParsedObj {
  std::vector<std::string> groups;
  std::vector<std::size_t> group_first_v;  // index of the group's first vertex
  std::vector<Eigen::Vector3f> v, vn;
  std::vector<Eigen::Vector2f> vt;
  std::vector<std::array<long, 3>> f, ft, fn;  // 1-based; ft, fn = -1 when absent
  std::vector<std::string> corners;            // the first corner of each face as written
  std::string layout;                          // the line tags in order, runs of one tag once: "o v vt f ..."
};

Eigen::Vector3f parse_xyz(std::istringstream& ls) {
  std::string x, y, z;
  ls >> x >> y >> z;
  return {std::strtof(x.c_str(), nullptr), std::strtof(y.c_str(), nullptr), std::strtof(z.c_str(), nullptr)};
}

ParsedObj parse_obj(const std::string& text) {
  ParsedObj o;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (!tag.empty() && tag[0] != '#' && !o.layout.ends_with(" " + tag) && o.layout != tag)
      o.layout += (o.layout.empty() ? "" : " ") + tag;
    if (tag == "o") {
      std::string name;
      ls >> name;
      o.groups.push_back(name);
      o.group_first_v.push_back(o.v.size());
    } else if (tag == "v") {
      o.v.push_back(parse_xyz(ls));
    } else if (tag == "vt") {
      std::string x, y;
      ls >> x >> y;
      o.vt.emplace_back(std::strtof(x.c_str(), nullptr), std::strtof(y.c_str(), nullptr));
    } else if (tag == "vn") {
      o.vn.push_back(parse_xyz(ls));
    } else if (tag == "f") {
      // Each corner is v, v/vt, v//vn or v/vt/vn.
      std::array<long, 3> a{}, b{-1, -1, -1}, n{-1, -1, -1};
      for (int c = 0; c < 3; ++c) {
        std::string tok;
        ls >> tok;
        if (c == 0) o.corners.push_back(tok);
        std::vector<std::string> fields{""};
        for (const char ch : tok) {
          if (ch == '/')
            fields.emplace_back();
          else
            fields.back() += ch;
        }
        EXPECT_LE(fields.size(), 3u) << line;
        a[c] = std::stol(fields[0]);
        if (fields.size() > 1 && !fields[1].empty()) b[c] = std::stol(fields[1]);
        if (fields.size() > 2) n[c] = std::stol(fields[2]);
        EXPECT_FALSE(fields.size() == 2 && fields[1].empty()) << "empty texture index: " << line;
      }
      std::string extra;
      EXPECT_FALSE(ls >> extra) << "face with more than 3 vertices: " << line;
      o.f.push_back(a);
      o.ft.push_back(b);
      o.fn.push_back(n);
    } else {
      EXPECT_TRUE(tag.empty() || tag[0] == '#') << "unexpected OBJ line: " << line;
    }
  }
  return o;
}

TEST(MeshWriter, ObjRoundTrip) {
  TempDir dir;
  const Frame fr = make_frame();
  write_mesh(fr.meshes, fr.posed, dir.path() / "frame.obj");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.obj"});
  const ParsedObj o = parse_obj(read_text(dir.path() / "frame.obj"));
  EXPECT_EQ(o.groups, (std::vector<std::string>{"tet_one", "mesh1"}));
  EXPECT_EQ(o.group_first_v, (std::vector<std::size_t>{0, 4}));
  EXPECT_TRUE(o.vn.empty()) << "rest normals must not be written for a posed frame";
  ASSERT_EQ(o.v.size(), 8u);
  ASSERT_EQ(o.vt.size(), 4u);  // only the tetrahedron has texture coordinates
  ASSERT_EQ(o.f.size(), 6u);
  std::size_t v0 = 0, f0 = 0;
  for (std::size_t m = 0; m < fr.meshes.size(); ++m) {
    const Mesh& mesh = fr.meshes[m];
    for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(o.v[v0 + v][c], fr.posed[m](v, c)) << "mesh " << m << " vertex " << v;
    for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(o.f[f0 + f][c], static_cast<long>(v0 + mesh.faces(f, c) + 1));
        if (mesh.uvs.rows() > 0) {
          EXPECT_EQ(o.ft[f0 + f][c], mesh.faces(f, c) + 1);
          EXPECT_EQ(o.vt[mesh.faces(f, c)], Eigen::Vector2f(mesh.uvs.row(mesh.faces(f, c)).transpose()));
        } else {
          EXPECT_EQ(o.ft[f0 + f][c], -1);
        }
        EXPECT_EQ(o.fn[f0 + f][c], -1);
      }
    v0 += static_cast<std::size_t>(mesh.vertex_count());
    f0 += static_cast<std::size_t>(mesh.face_count());
  }
}

TEST(MeshWriter, ObjWritesPosedNormals) {
  // With normals for both meshes, and for the quad only: vn lines follow each mesh's vt lines,
  // and faces are v/vt/vn (texture coordinates and normals) or v//vn (normals only), vn
  // counted over the whole file like v and vt.
  for (const bool tet_normals : {true, false}) {
    SCOPED_TRACE(tet_normals ? "both meshes with normals" : "the quad with normals");
    TempDir dir;
    Frame fr = make_frame();
    if (!tet_normals) fr.normals[0].resize(0, 3);
    write_mesh(fr.meshes, fr.posed, dir.path() / "frame.obj", fr.normals);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.obj"});
    const ParsedObj o = parse_obj(read_text(dir.path() / "frame.obj"));
    EXPECT_EQ(o.layout, tet_normals ? "o v vt vn f o v vn f" : "o v vt f o v vn f");
    ASSERT_EQ(o.v.size(), 8u);
    ASSERT_EQ(o.vt.size(), 4u);
    ASSERT_EQ(o.vn.size(), tet_normals ? 8u : 4u);
    ASSERT_EQ(o.f.size(), 6u);
    EXPECT_EQ(o.corners[0], tet_normals ? "1/1/1" : "1/1");  // tet face 0 starts at vertex 0
    EXPECT_EQ(o.corners[4], tet_normals ? "5//5" : "5//1");  // quad face 0 starts at vertex 0
    std::size_t v0 = 0, vn0 = 0, f0 = 0;
    for (std::size_t m = 0; m < fr.meshes.size(); ++m) {
      const Mesh& mesh = fr.meshes[m];
      const RowMatrixXf<3>& n = fr.normals[m];
      for (Eigen::Index v = 0; v < n.rows(); ++v)
        EXPECT_EQ(o.vn[vn0 + v], Eigen::Vector3f(n.row(v).transpose())) << "mesh " << m << " normal " << v;
      for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
        for (int c = 0; c < 3; ++c) {
          EXPECT_EQ(o.f[f0 + f][c], static_cast<long>(v0 + mesh.faces(f, c) + 1));
          EXPECT_EQ(o.ft[f0 + f][c], mesh.uvs.rows() > 0 ? mesh.faces(f, c) + 1 : -1);
          EXPECT_EQ(o.fn[f0 + f][c], n.rows() > 0 ? static_cast<long>(vn0 + mesh.faces(f, c) + 1) : -1);
        }
      v0 += static_cast<std::size_t>(mesh.vertex_count());
      vn0 += static_cast<std::size_t>(n.rows());
      f0 += static_cast<std::size_t>(mesh.face_count());
    }
  }
}

/// A binary little-endian PLY as cgamesh writes it: the header, and the vertex element's float
/// properties, one row per vertex.
struct ParsedPly {
  std::string header;
  std::vector<std::vector<float>> vertices;
  std::vector<std::array<std::int32_t, 3>> faces;
};

ParsedPly parse_ply(const std::string& bytes, std::size_t vertex_properties) {
  ParsedPly ply;
  const std::string end = "end_header\n";
  const auto header_end = bytes.find(end);
  if (header_end == std::string::npos) {
    ADD_FAILURE() << "no end_header";
    return ply;
  }
  ply.header = bytes.substr(0, header_end + end.size());
  const auto count = [&](const std::string& element) {
    const auto at = ply.header.find("element " + element + " ");
    return at == std::string::npos ? 0 : std::stoul(ply.header.substr(at + element.size() + 9));
  };
  const std::size_t nv = count("vertex"), nf = count("face");
  if (bytes.size() != ply.header.size() + nv * 4 * vertex_properties + nf * 13) {
    ADD_FAILURE() << bytes.size() << " bytes for " << nv << " vertices of " << vertex_properties << " properties and "
                  << nf << " faces";
    return ply;
  }
  const char* p = bytes.data() + ply.header.size();
  const auto u32 = [&p] {
    std::uint32_t v = 0;
    for (int b = 0; b < 4; ++b) v |= std::uint32_t(static_cast<unsigned char>(*p++)) << (8 * b);
    return v;
  };
  for (std::size_t v = 0; v < nv; ++v) {
    std::vector<float>& row = ply.vertices.emplace_back();
    for (std::size_t c = 0; c < vertex_properties; ++c) {
      const std::uint32_t bits = u32();
      float x;
      std::memcpy(&x, &bits, 4);
      row.push_back(x);
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    EXPECT_EQ(*p++, 3);
    std::array<std::int32_t, 3>& face = ply.faces.emplace_back();
    for (int c = 0; c < 3; ++c) face[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(u32());
  }
  return ply;
}

TEST(MeshWriter, PlyWritesPosedNormals) {
  TempDir dir;
  const Frame fr = make_frame();
  write_mesh(fr.meshes, fr.posed, dir.path() / "frame.ply", fr.normals);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.ply"});
  const ParsedPly ply = parse_ply(read_text(dir.path() / "frame.ply"), 6);
  EXPECT_EQ(ply.header,
            "ply\nformat binary_little_endian 1.0\ncomment generated by cgamesh\nelement vertex 8\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\nelement face 6\n"
            "property list uchar int vertex_indices\nend_header\n");
  ASSERT_EQ(ply.vertices.size(), 8u);
  ASSERT_EQ(ply.faces.size(), 6u);
  std::size_t row = 0, face = 0;
  std::int32_t base = 0;
  for (std::size_t m = 0; m < fr.meshes.size(); ++m) {
    for (Eigen::Index v = 0; v < fr.posed[m].rows(); ++v, ++row)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(ply.vertices[row][static_cast<std::size_t>(c)], fr.posed[m](v, c));
        EXPECT_EQ(ply.vertices[row][static_cast<std::size_t>(3 + c)], fr.normals[m](v, c));
      }
    for (Eigen::Index f = 0; f < fr.meshes[m].face_count(); ++f, ++face)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(ply.faces[face][static_cast<std::size_t>(c)], base + fr.meshes[m].faces(f, c));
    base += static_cast<std::int32_t>(fr.meshes[m].vertex_count());
  }
}

TEST(MeshWriter, PlyNormalsOnlyWhenEveryMeshHasThem) {
  // One vertex element holds every mesh: a mesh without normals leaves the file without them.
  TempDir dir;
  Frame fr = make_frame();
  fr.normals[1].resize(0, 3);
  write_mesh(fr.meshes, fr.posed, dir.path() / "frame.ply", fr.normals);
  const ParsedPly ply = parse_ply(read_text(dir.path() / "frame.ply"), 3);
  EXPECT_EQ(ply.header.find("property float nx"), std::string::npos) << ply.header;
  ASSERT_EQ(ply.vertices.size(), 8u);
  EXPECT_EQ(ply.vertices[7][2], fr.posed[1](3, 2));
  // A mesh without vertices needs none.
  Frame empty = make_frame();
  empty.meshes[1].positions.resize(0, 3);
  empty.meshes[1].faces.resize(0, 3);
  empty.posed[1].resize(0, 3);
  empty.normals[1].resize(0, 3);
  write_mesh(empty.meshes, empty.posed, dir.path() / "tet.ply", empty.normals);
  const ParsedPly tet = parse_ply(read_text(dir.path() / "tet.ply"), 6);
  ASSERT_EQ(tet.vertices.size(), 4u);
  EXPECT_EQ(tet.vertices[3][5], empty.normals[0](3, 2));
}

TEST(MeshWriter, PlyRoundTrip) {
  TempDir dir;
  const Frame fr = make_frame();
  write_mesh(fr.meshes, fr.posed, dir.path() / "frame.PLY");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frame.PLY"});
  const std::string bytes = read_text(dir.path() / "frame.PLY");
  const std::string end = "end_header\n";
  const auto header_end = bytes.find(end);
  ASSERT_NE(header_end, std::string::npos);
  const std::string header = bytes.substr(0, header_end + end.size());
  EXPECT_EQ(header,
            "ply\nformat binary_little_endian 1.0\ncomment generated by cgamesh\nelement vertex 8\n"
            "property float x\nproperty float y\nproperty float z\nelement face 6\n"
            "property list uchar int vertex_indices\nend_header\n");
  const unsigned char* p = reinterpret_cast<const unsigned char*>(bytes.data()) + header.size();
  auto u32 = [&p] {
    const std::uint32_t v =
        std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
    p += 4;
    return v;
  };
  ASSERT_EQ(bytes.size(), header.size() + std::size_t{8 * 12 + 6 * 13});
  for (std::size_t m = 0; m < fr.meshes.size(); ++m)
    for (Eigen::Index v = 0; v < fr.posed[m].rows(); ++v)
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t bits = u32();
        float x;
        std::memcpy(&x, &bits, 4);
        EXPECT_EQ(x, fr.posed[m](v, c));
      }
  std::int64_t base = 0;
  for (const Mesh& mesh : fr.meshes) {
    for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
      EXPECT_EQ(*p++, 3);
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(static_cast<std::int64_t>(static_cast<std::int32_t>(u32())), base + mesh.faces(f, c));
    }
    base += mesh.vertex_count();
  }
}

TEST(MeshWriter, ReplacesAnExistingFile) {
  TempDir dir;
  const Frame fr = make_frame();
  { std::ofstream(dir.path() / "f.obj") << "old content\n"; }
  write_mesh(fr.meshes, fr.posed, dir.path() / "f.obj");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"f.obj"});
  EXPECT_EQ(parse_obj(read_text(dir.path() / "f.obj")).v.size(), 8u);
}

template <class Mutate>
void expect_rejected(Mutate mutate) {
  for (const char* name : {"bad.obj", "bad.ply"}) {
    TempDir dir;
    Frame fr = make_frame();
    mutate(fr);
    EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / name, fr.normals), InvalidInputError) << name;
    EXPECT_TRUE(dir.entries().empty()) << name;
  }
}

TEST(MeshWriterErrors, UnknownExtension) {
  TempDir dir;
  const Frame fr = make_frame();
  EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / "f.stl"), InvalidInputError);
  EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / "f"), InvalidInputError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(MeshWriterErrors, NoMeshes) {
  expect_rejected([](Frame& f) {
    f.meshes.clear();
    f.posed.clear();
  });
}

TEST(MeshWriterErrors, PositionSetCountMismatch) {
  expect_rejected([](Frame& f) { f.posed.pop_back(); });
}

TEST(MeshWriterErrors, PositionRowsMismatch) {
  expect_rejected([](Frame& f) { f.posed[1].conservativeResize(3, 3); });
}

TEST(MeshWriterErrors, NanPosition) {
  expect_rejected([](Frame& f) { f.posed[1](2, 0) = std::nanf(""); });
}

TEST(MeshWriterErrors, FaceIndexOutOfRange) {
  expect_rejected([](Frame& f) { f.meshes[0].faces(1, 1) = 4; });
}

TEST(MeshWriterErrors, UvRowsMismatch) {
  expect_rejected([](Frame& f) { f.meshes[0].uvs.conservativeResize(2, 2); });
}

TEST(MeshWriterErrors, NormalSetCountMismatch) {
  expect_rejected([](Frame& f) { f.normals.pop_back(); });
}

TEST(MeshWriterErrors, NormalRowsMismatch) {
  expect_rejected([](Frame& f) { f.normals[0].conservativeResize(3, 3); });
}

TEST(MeshWriterErrors, NanOrInfiniteNormal) {
  expect_rejected([](Frame& f) { f.normals[1](2, 1) = std::nanf(""); });
  expect_rejected([](Frame& f) { f.normals[0](3, 2) = -INFINITY; });
}

TEST(MeshWriterErrors, MissingDirectoryIsAWriteError) {
  TempDir dir;
  const Frame fr = make_frame();
  EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / "missing" / "f.ply"), cgamesh::WriteError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
