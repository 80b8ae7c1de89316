// Mesh::file_index: each loaded vertex keeps its number in the file (glTF accessor, PLY
// element, OBJ `v` line), through joining and seams.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
namespace fs = std::filesystem;

fs::path write_text(const cgamesh_test::TempDir& dir, const std::string& name, const std::string& text) {
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

/// The positions of the `v` lines and the `v` index (from 0) of each triangle corner, in order.
struct ObjFile {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
};

ObjFile read_obj(const fs::path& path) {
  ObjFile obj;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "v") {
      Eigen::Vector3d p;
      words >> p.x() >> p.y() >> p.z();
      obj.v.push_back(p);
    } else if (key == "f") {
      std::vector<int> corner;
      for (std::string c; words >> c;) corner.push_back(std::stoi(c.substr(0, c.find('/'))) - 1);
      for (std::size_t k = 2; k < corner.size(); ++k) obj.f.push_back({corner[0], corner[k - 1], corner[k]});
    }
  }
  return obj;
}

// Real scans as Assimp reads them (one vertex per corner, then joined): every corner of every
// triangle is numbered by the `v` line its `f` entry names, or by the first `v` line at the same
// place. Faces keep the file's order here (one group, triangles).
TEST(FileVertices, ObjCornersKeepTheirVLines) {
  for (const char* name : {"cow.obj", "spot.obj"}) {
    SCOPED_TRACE(name);
    const fs::path path = cgamesh_test::asset(name);
    const ObjFile obj = read_obj(path);
    const mesh::Mesh m = io::load_model(path).meshes.at(0);
    ASSERT_EQ(m.file_index.rows(), m.vertex_count());
    ASSERT_EQ(static_cast<std::size_t>(m.face_count()), obj.f.size());
    int exact = 0;
    for (Eigen::Index f = 0; f < m.face_count(); ++f)
      for (int c = 0; c < 3; ++c) {
        const int named = obj.f[static_cast<std::size_t>(f)][static_cast<std::size_t>(c)];
        const int got = m.file_index[m.faces(f, c)];
        ASSERT_GE(got, 0);
        ASSERT_LE(got, named) << "face " << f;
        EXPECT_EQ(obj.v[static_cast<std::size_t>(got)], obj.v[static_cast<std::size_t>(named)]) << "face " << f;
        exact += got == named ? 1 : 0;
      }
    EXPECT_GT(exact, 0.99 * 3 * static_cast<double>(m.face_count()));
  }
}

// A hand-made OBJ: `v` lines in another order than the faces use them, an unused line, a
// repeated position, a quad, a UV seam and two groups (Assimp makes two meshes).
TEST(FileVertices, ObjNumberingAcrossGroupsSeamsAndRepeats) {
  cgamesh_test::TempDir dir;
  const fs::path path = write_text(dir, "numbered.obj",
                                   "v 0.5 0.5 0.5\n"        // 0: on no face
                                   "v 1 1 0\n"              // 1
                                   "v 0 1 0\n"              // 2
                                   "v 0 0 0\n"              // 3
                                   "v 1 0 0\n"              // 4
                                   "v 0 0 0\n"              // 5: the same place as 3
                                   "v 2 0.1 0.333333333\n"  // 6
                                   "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                                   "f 4/1 5/2 2/3 3/4\n"
                                   "g other\n"
                                   "f 5/5 7/2 2/3\n"
                                   "f 6/1 5/1 2/3\n");
  const anim::RiggedModel model = io::load_model(path);
  ASSERT_EQ(model.meshes.size(), 2u);
  const std::vector<Eigen::Vector3f> at = {
      {0.5f, 0.5f, 0.5f}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {2, 0.1f, 0.333333333f}};
  for (const mesh::Mesh& m : model.meshes) {
    ASSERT_EQ(m.file_index.rows(), m.vertex_count()) << m.name;
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const int f = m.file_index[v];
      ASSERT_TRUE(f >= 1 && f <= 6) << f;
      EXPECT_NE(f, 5) << "a repeated position is numbered by its first line";
      EXPECT_LT((m.positions.row(v).transpose() - at[static_cast<std::size_t>(f)]).norm(), 1e-6f);
    }
  }
  // `v` line 4 is used with two UVs in the second group: two vertices, one number.
  const mesh::Mesh& second = model.meshes[1];
  EXPECT_EQ((second.file_index.array() == 4).count(), 2);
}

// PLY and glTF: Assimp keeps the file's vertex order, so the numbering is the identity —
// unused vertices included; a PLY soup's copies are joined into their first vertex.
TEST(FileVertices, PlyAndGltfAreNumberedAsStored) {
  cgamesh_test::TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const mesh::Mesh indexed =
      io::load_model(
          write_text(dir, "indexed.ply", header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n9 9 9\n0 0 1\n3 3 2 1\n3 0 1 3\n"))
          .meshes.at(0);
  EXPECT_EQ(indexed.file_index, Eigen::VectorXi::LinSpaced(6, 0, 5));
  const mesh::Mesh soup =
      io::load_model(
          write_text(dir, "soup.ply", header + "0 0 0\n1 0 0\n0 1 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 3 4 5\n"))
          .meshes.at(0);
  ASSERT_EQ(soup.vertex_count(), 4);
  EXPECT_EQ(soup.file_index, (Eigen::VectorXi(4) << 0, 1, 2, 4).finished());

  const mesh::Mesh man = io::load_model(cgamesh_test::demo_model()).meshes.at(0);
  EXPECT_EQ(man.file_index,
            Eigen::VectorXi::LinSpaced(man.vertex_count(), 0, static_cast<int>(man.vertex_count()) - 1));
  // Formats whose numbering Assimp does not keep have none.
  EXPECT_EQ(io::load_model(cgamesh_test::assimp_model("X/Testwuson.X")).meshes.at(0).file_index.rows(), 0);
}

}  // namespace
