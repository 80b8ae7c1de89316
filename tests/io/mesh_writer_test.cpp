// write_mesh: posed frames written as OBJ and PLY are parsed back by small independent readers
// and compared; invalid input throws and leaves nothing behind.

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
};

/// Two meshes: a tetrahedron with texture coordinates ("tet one", a name with a space) and a
/// quad without; posed positions differ from the rest positions and have awkward digits.
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
  std::vector<Eigen::Vector3f> v;
  std::vector<Eigen::Vector2f> vt;
  std::vector<std::array<long, 3>> f, ft;  // 1-based; ft = -1 when absent
  int vn = 0;
};

ParsedObj parse_obj(const std::string& text) {
  ParsedObj o;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "o") {
      std::string name;
      ls >> name;
      o.groups.push_back(name);
      o.group_first_v.push_back(o.v.size());
    } else if (tag == "v") {
      std::string x, y, z;
      ls >> x >> y >> z;
      o.v.emplace_back(std::strtof(x.c_str(), nullptr), std::strtof(y.c_str(), nullptr),
                       std::strtof(z.c_str(), nullptr));
    } else if (tag == "vt") {
      std::string x, y;
      ls >> x >> y;
      o.vt.emplace_back(std::strtof(x.c_str(), nullptr), std::strtof(y.c_str(), nullptr));
    } else if (tag == "vn") {
      ++o.vn;
    } else if (tag == "f") {
      std::array<long, 3> a{}, b{-1, -1, -1};
      for (int c = 0; c < 3; ++c) {
        std::string tok;
        ls >> tok;
        a[c] = std::stol(tok);
        if (const auto slash = tok.find('/'); slash != std::string::npos) b[c] = std::stol(tok.substr(slash + 1));
      }
      std::string extra;
      EXPECT_FALSE(ls >> extra) << "face with more than 3 vertices: " << line;
      o.f.push_back(a);
      o.ft.push_back(b);
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
  EXPECT_EQ(o.vn, 0) << "rest normals must not be written for a posed frame";
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
      }
    v0 += static_cast<std::size_t>(mesh.vertex_count());
    f0 += static_cast<std::size_t>(mesh.face_count());
  }
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
    EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / name), InvalidInputError) << name;
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

TEST(MeshWriterErrors, MissingDirectoryIsAWriteError) {
  TempDir dir;
  const Frame fr = make_frame();
  EXPECT_THROW(write_mesh(fr.meshes, fr.posed, dir.path() / "missing" / "f.ply"), cgamesh::WriteError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
