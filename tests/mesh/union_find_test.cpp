#include "cgamesh/mesh/union_find.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace {

using cgamesh::mesh::UnionFind;

TEST(UnionFind, RootIsTheSmallestElementWhateverTheOrderOfUnions) {
  UnionFind a(6), b(6);
  a.unite(5, 3);
  a.unite(3, 1);
  a.unite(4, 2);
  b.unite(1, 3);
  b.unite(2, 4);
  b.unite(3, 5);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(a.find(i), b.find(i));
  EXPECT_EQ(a.find(5), 1);
  EXPECT_EQ(a.find(4), 2);
  EXPECT_EQ(a.find(0), 0);
  a.unite(4, 5);
  EXPECT_EQ(a.find(2), 1);
}

TEST(UnionFind, AgreesWithLabelPropagationOnRandomGraphs) {
  std::mt19937 rng(11);
  for (int round = 0; round < 20; ++round) {
    const int n = 200;
    std::uniform_int_distribution<int> node(0, n - 1);
    UnionFind sets(n);
    std::vector<int> label(n);
    for (int i = 0; i < n; ++i) label[static_cast<std::size_t>(i)] = i;
    for (int e = 0; e < 150; ++e) {
      const int a = node(rng), b = node(rng);
      sets.unite(a, b);
      const int from = label[static_cast<std::size_t>(a)], to = label[static_cast<std::size_t>(b)];
      for (int& l : label)
        if (l == from || l == to) l = std::min(from, to);
    }
    for (int i = 0; i < n; ++i) ASSERT_EQ(sets.find(i), label[static_cast<std::size_t>(i)]) << i;
  }
}

}  // namespace
