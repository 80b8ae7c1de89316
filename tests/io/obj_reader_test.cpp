// io::read_obj: the one OBJ line reader (cages, and the file numbering of loaded OBJ meshes).

#include "cgamesh/io/obj_reader.hpp"

#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "support/temp_dir.hpp"

namespace {

using cgamesh::FileError;
using cgamesh::io::ObjPolygons;
using cgamesh::io::read_obj;
using cgamesh_test::TempDir;

std::string error_of(const std::filesystem::path& path, const cgamesh::io::ObjReadOptions& options = {}) {
  try {
    (void)read_obj(path, options);
  } catch (const FileError& e) {
    return e.what();
  }
  return "no FileError";
}

TEST(ObjReader, ReadsVerticesInFileOrderAndFansPolygons) {
  TempDir dir;
  std::ofstream(dir / "a.obj") << "# comment\nvn 0 0 1\nv 0 0 0\nv +1 0 0 0.5\n  v\t0 1 0\nvt 0.5 0.5\nv 0 0 1e0\n"
                                  "f 1 3 2\nf 1/1 2/2 4/4\nf -4 -1 -2\nf 2//1 3//1 4//1 1//1\ng part\no x\n";
  const ObjPolygons obj = read_obj(dir / "a.obj");
  ASSERT_EQ(obj.vertices.rows(), 4);
  EXPECT_EQ(obj.vertices.row(1), Eigen::RowVector3d(1, 0, 0));  // '+' and a w coordinate
  EXPECT_EQ(obj.vertices.row(2), Eigen::RowVector3d(0, 1, 0));  // indented, tab-separated
  EXPECT_EQ(obj.vertices.row(3), Eigen::RowVector3d(0, 0, 1));
  ASSERT_EQ(obj.faces.rows(), 5);
  EXPECT_EQ(obj.faces.row(0), Eigen::RowVector3i(0, 2, 1));
  EXPECT_EQ(obj.faces.row(2), Eigen::RowVector3i(0, 3, 2));  // negative: counted back from the last vertex
  EXPECT_EQ(obj.faces.row(3), Eigen::RowVector3i(1, 2, 3));  // a quad, fanned from its first corner
  EXPECT_EQ(obj.faces.row(4), Eigen::RowVector3i(1, 3, 0));
}

TEST(ObjReader, StrictErrorsNameTheFileAndLine) {
  TempDir dir;
  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "bad.obj") << text;
    return dir / "bad.obj";
  };
  const cgamesh::io::ObjReadOptions cage{.strict = true, .what = "cage"};
  const std::string path = (dir / "bad.obj").string();
  EXPECT_EQ(error_of(write("v 0 0 0\nv 1 0\n"), cage), "cage " + path + ":2: expected v x y z (finite numbers)");
  EXPECT_EQ(error_of(write("v 0 zero 0\n"), cage), "cage " + path + ":1: expected v x y z (finite numbers)");
  EXPECT_EQ(error_of(write("v 0 0 nan\n"), cage), "cage " + path + ":1: expected v x y z (finite numbers)");
  EXPECT_EQ(error_of(write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), cage),
            "cage " + path + ":4: vertex index 4 out of range (3 vertices so far)");
  EXPECT_EQ(error_of(write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n"), cage),
            "cage " + path + ":4: vertex index 0 out of range (3 vertices so far)");
  EXPECT_EQ(error_of(write("v 0 0 0\nf 1 a 2\n"), cage), "cage " + path + ":2: expected f with vertex indices, got 'a'");
  EXPECT_EQ(error_of(write("v 0 0 0\nv 1 0 0\nf 1 2\n"), cage), "cage " + path + ":3: a face needs 3 vertices or more");
  EXPECT_EQ(error_of(dir / "missing.obj"), "cannot read the OBJ " + (dir / "missing.obj").string());
  EXPECT_EQ(error_of(dir.path()), "cannot read the OBJ " + dir.path().string() + ": is a directory");
}

TEST(ObjReader, LenientKeepsEveryVertexLineInPlaceAndSkipsFaces) {
  TempDir dir;
  std::ofstream(dir / "a.obj") << "v 0 0 0\nv 1 x 2\nv 3\nv 4 5 6\nf 1 2 99\n";
  const ObjPolygons obj = read_obj(dir / "a.obj", {.strict = false});
  ASSERT_EQ(obj.vertices.rows(), 4);
  EXPECT_EQ(obj.vertices(1, 0), 1);
  EXPECT_TRUE(std::isnan(obj.vertices(1, 1)));
  EXPECT_EQ(obj.vertices(1, 2), 2);
  EXPECT_EQ(obj.vertices(2, 0), 3);
  EXPECT_TRUE(std::isnan(obj.vertices(2, 2)));
  EXPECT_EQ(obj.vertices.row(3), Eigen::RowVector3d(4, 5, 6));  // still the 4th line
  EXPECT_EQ(obj.faces.rows(), 0);
}

}  // namespace
