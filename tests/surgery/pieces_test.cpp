#include "cgamesh/surgery/pieces.hpp"

#include <gtest/gtest.h>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/surgery/cut.hpp"

#include "surgery/surgery_fixtures.hpp"

namespace {

namespace surgery = cgamesh::surgery;
namespace cga = cgamesh::cga;
using cgamesh::mesh::Mesh;

TEST(Pieces, SeamCopiesAreOnePieceAndSeparateCubesAreTwo) {
  Mesh two = cgamesh_test::cube();
  // A second cube, moved away, plus a seam: vertex 8 is a copy of vertex 0 used by one face.
  Mesh other = cgamesh_test::cube();
  other.positions.rowwise() += Eigen::RowVector3f(3, 0, 0);
  const Eigen::Index n = two.vertex_count();
  two.positions.conservativeResize(2 * n + 1, 3);
  two.positions.middleRows(n, n) = other.positions;
  two.positions.row(2 * n) = two.positions.row(0);
  two.faces.conservativeResize(24, 3);
  two.faces.bottomRows(12) = other.faces.array() + static_cast<int>(n);
  two.faces(0, 0) = static_cast<int>(2 * n);
  const surgery::Pieces p = surgery::pieces(two);
  EXPECT_EQ(p.count, 2);
  EXPECT_EQ(p.of_vertex[0], p.of_vertex[static_cast<std::size_t>(2 * n)]);
  EXPECT_EQ(p.of_vertex[1], 0);
  EXPECT_EQ(p.of_vertex[static_cast<std::size_t>(n)], 1);
}

TEST(Pieces, AVertexInNoFaceHasNoPiece) {
  Mesh m = cgamesh_test::cube();
  m.positions.conservativeResize(9, 3);
  m.positions.row(8) << 5, 5, 5;
  const surgery::Pieces p = surgery::pieces(m);
  EXPECT_EQ(p.count, 1);
  EXPECT_EQ(p.of_vertex[8], -1);
  m.faces(0, 0) = 9;
  EXPECT_THROW(static_cast<void>(surgery::pieces(m)), cgamesh::InvalidInputError);
}

TEST(Pieces, CesiumManIsOnePieceAndACutThroughTheArmsMakesMore) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  EXPECT_EQ(surgery::pieces(model.meshes[0]).count, 1);
  // At t = 0.5 a horizontal plane at the waist also cuts both forearms: the lower side keeps
  // the legs and the two hands apart.
  const auto placement = surgery::place(
      model, cgamesh::anim::sample(model.skeleton, model.clips[0], 0.5, cgamesh::anim::BlendMode::format));
  const surgery::ModelCut c = surgery::cut(model, placement, cga::plane<double>({0, 1, 0}, 0.9));
  EXPECT_EQ(surgery::pieces(c.pieces[0].meshes[0]).count, 1);
  EXPECT_GE(surgery::pieces(c.pieces[1].meshes[0]).count, 2);
}

}  // namespace
