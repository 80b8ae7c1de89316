// Face adjacency across welded edges: twins are the only two face edges on a welded edge, in
// opposite directions.
#include "cgamesh/mesh/adjacency.hpp"

#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

using namespace cgamesh;

TEST(Adjacency, TwoTrianglesAcrossASeam) {
  // Square 0-1-2-3 split along 0-2, the second triangle using seam copies 4 (of 0) and 5 (of 2).
  mesh::Faces f(2, 3);
  f << 0, 1, 2,  //
      4, 5, 3;
  const std::vector<int> weld{0, 1, 2, 3, 0, 2};
  const mesh::FaceNeighbors n = mesh::face_adjacency(f, weld);
  EXPECT_EQ(n[0], (std::array<int, 3>{-1, -1, 1}));
  EXPECT_EQ(n[1], (std::array<int, 3>{0, -1, -1}));
  EXPECT_EQ(mesh::edge_across(n, 0, 2), 0);
  EXPECT_EQ(mesh::edge_across(n, 1, 0), 2);
  EXPECT_EQ(mesh::edge_across(n, 0, 0), -1);
  // Without the welding the seam is a boundary.
  const mesh::FaceNeighbors apart = mesh::face_adjacency(f, std::vector<int>{0, 1, 2, 3, 4, 5});
  EXPECT_EQ(apart[0][2], -1);
}

TEST(Adjacency, NonManifoldFlippedAndDegenerateEdgesHaveNoNeighbour) {
  mesh::Faces f(5, 3);
  f << 0, 1, 2,  // edge 0-1 shared by three faces
      1, 0, 3,   //
      0, 1, 4,   //
      2, 1, 5,   // 2-1: the twin of face 0's 1-2
      5, 5, 6;   // its edge 5-5 is degenerate
  const std::vector<int> weld{0, 1, 2, 3, 4, 5, 6};
  const mesh::FaceNeighbors n = mesh::face_adjacency(f, weld);
  EXPECT_EQ(n[0][0], -1);
  EXPECT_EQ(n[1][0], -1);
  EXPECT_EQ(n[2][0], -1);
  EXPECT_EQ(n[0][1], 3);
  EXPECT_EQ(n[3][0], 0);
  EXPECT_EQ(n[4][0], -1);
  mesh::Faces same(2, 3);
  same << 0, 1, 2,  //
      0, 1, 3;      // 0-1 twice in one direction: inconsistently oriented
  const mesh::FaceNeighbors s = mesh::face_adjacency(same, std::vector<int>{0, 1, 2, 3});
  EXPECT_EQ(s[0][0], -1);
  EXPECT_EQ(s[1][0], -1);
}

TEST(Adjacency, LinkingSomeEdgesAgreesWithTheWholeMesh) {
  // A 4×4 grid of quads, each split in two.
  const int n = 5;
  mesh::Faces f(2 * (n - 1) * (n - 1), 3);
  int r = 0;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      f.row(r++) << a, b, d;
      f.row(r++) << a, d, c;
    }
  std::vector<int> weld(n * n);
  for (int v = 0; v < n * n; ++v) weld[static_cast<std::size_t>(v)] = v;
  const mesh::FaceNeighbors whole = mesh::face_adjacency(f, weld);
  // Forget faces 10 … 13 and relink their edges and the edges of the faces next to them.
  mesh::FaceNeighbors part = whole;
  std::vector<std::array<int, 2>> edges;
  for (int g = 10; g < 14; ++g)
    for (int k = 0; k < 3; ++k) {
      part[static_cast<std::size_t>(g)][static_cast<std::size_t>(k)] = -7;
      edges.push_back({g, k});
      const int h = whole[static_cast<std::size_t>(g)][static_cast<std::size_t>(k)];
      if (h >= 0 && (h < 10 || h >= 14)) edges.push_back({h, mesh::edge_across(whole, g, k)});
    }
  mesh::link_twins(f, weld, edges, part);
  EXPECT_EQ(part, whole);
  EXPECT_THROW(static_cast<void>(mesh::face_adjacency(f, std::vector<int>{0, 1})), InvalidInputError);
}

}  // namespace
