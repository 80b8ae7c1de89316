// The BVH edited face by face (replace, append, erase) answers every query as a BVH built from
// scratch over the same triangles does.
#include "cgamesh/mesh/triangle_bvh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

using namespace cgamesh;
using Triangle = std::array<Eigen::Vector3f, 3>;

/// A BVH built from scratch over `tris` (face i = tris[i]).
mesh::TriangleBvh fresh(const std::vector<Triangle>& tris) {
  mesh::RowMatrixXf<3> p(static_cast<Eigen::Index>(3 * tris.size()), 3);
  mesh::TriangleBvh::Faces f(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t i = 0; i < tris.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) p.row(static_cast<Eigen::Index>(3 * i + k)) = tris[i][k].transpose();
    f.row(static_cast<Eigen::Index>(i)) << static_cast<int>(3 * i), static_cast<int>(3 * i + 1),
        static_cast<int>(3 * i + 2);
  }
  return {p, f};
}

Triangle random_triangle(std::mt19937& rng, float size) {
  std::uniform_real_distribution<float> at(0, 10), off(-size, size);
  const Eigen::Vector3f c(at(rng), at(rng), at(rng) * 0.1f);
  Triangle t;
  for (auto& x : t) x = c + Eigen::Vector3f(off(rng), off(rng), off(rng));
  return t;
}

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(TriangleBvh, EditedTreeAnswersLikeAFreshOne) {
  std::mt19937 rng(11);
  std::vector<Triangle> tris;
  for (int i = 0; i < 500; ++i) tris.push_back(random_triangle(rng, 0.3f));
  mesh::TriangleBvh bvh = fresh(tris);
  std::uniform_real_distribution<double> coord(-1, 11);
  for (int round = 0; round < 40; ++round) {
    for (int op = 0; op < 25; ++op) {
      std::uniform_int_distribution<int> face(0, static_cast<int>(tris.size()) - 1);
      const int kind = op % 3, f = face(rng);
      if (kind == 0) {
        tris[static_cast<std::size_t>(f)] = random_triangle(rng, 0.5f);
        bvh.replace(f, tris[static_cast<std::size_t>(f)]);
      } else if (kind == 1) {
        tris.push_back(random_triangle(rng, 0.4f));
        bvh.append(tris.back(), f);
      } else {
        tris[static_cast<std::size_t>(f)] = tris.back();
        tris.pop_back();
        bvh.erase(f);
      }
    }
    ASSERT_EQ(bvh.face_count(), static_cast<int>(tris.size()));
    const mesh::TriangleBvh reference = fresh(tris);
    for (int q = 0; q < 20; ++q) {
      const Eigen::Vector3d a(coord(rng), coord(rng), 3), b(coord(rng), coord(rng), -3);
      const auto got = bvh.segment_hits(a, b), want = reference.segment_hits(a, b);
      ASSERT_EQ(got.size(), want.size());
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].face, want[i].face);
        EXPECT_DOUBLE_EQ(got[i].t, want[i].t);
      }
      // The box query may return a few more faces (whole leaves): it must return every face
      // whose own box meets the box. The slab query returns exactly the faces meeting the slab.
      const Eigen::Vector3d lo = a.cwiseMin(b), hi = lo + Eigen::Vector3d::Constant(1.5);
      const Eigen::Vector3d n = (b - a).normalized();
      const double d = n.dot(a), tolerance = 0.01;
      std::vector<int> in_box, near;
      bvh.faces_in_box(lo, hi, in_box);
      bvh.faces_near_plane(n, d, tolerance, near);
      in_box = sorted(in_box);
      near = sorted(near);
      for (const auto& found : {in_box, near}) {
        EXPECT_TRUE(std::adjacent_find(found.begin(), found.end()) == found.end()) << "a face twice";
        for (const int f : found) ASSERT_LT(f, static_cast<int>(tris.size()));
      }
      for (std::size_t f = 0; f < tris.size(); ++f) {
        Eigen::Vector3d tlo = Eigen::Vector3d::Constant(INFINITY), thi = -tlo;
        double smin = INFINITY, smax = -INFINITY;
        for (const auto& x : tris[f]) {
          tlo = tlo.cwiseMin(x.cast<double>());
          thi = thi.cwiseMax(x.cast<double>());
          smin = std::min(smin, n.dot(x.cast<double>()) - d);
          smax = std::max(smax, n.dot(x.cast<double>()) - d);
        }
        if ((tlo.array() <= hi.array()).all() && (thi.array() >= lo.array()).all()) {
          EXPECT_TRUE(std::binary_search(in_box.begin(), in_box.end(), static_cast<int>(f))) << f;
        }
        EXPECT_EQ(std::binary_search(near.begin(), near.end(), static_cast<int>(f)),
                  smin <= tolerance && smax >= -tolerance)
            << f;
      }
    }
  }
}

/// Distance from p to the segment [a, b].
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

// The drill's candidates: every face with a point within the radius of the segment (checked on a
// dense sampling of each face), each once, and only faces whose box comes near it — on a tree
// edited by appends, replacements and erasures too, and for segments along an axis.
TEST(TriangleBvh, FacesNearASegmentAreEveryFaceWithinTheRadius) {
  std::mt19937 rng(5);
  std::vector<Triangle> tris;
  for (int i = 0; i < 2000; ++i) tris.push_back(random_triangle(rng, 0.2f));
  mesh::TriangleBvh bvh = fresh(tris);
  for (int i = 0; i < 50; ++i) {
    tris.push_back(random_triangle(rng, 0.3f));
    bvh.append(tris.back(), i);
  }
  for (int i = 0; i < 60; ++i) {
    const int f = (37 * i) % static_cast<int>(tris.size());
    if (i % 2 == 0) {
      tris[static_cast<std::size_t>(f)] = random_triangle(rng, 0.3f);
      bvh.replace(f, tris[static_cast<std::size_t>(f)]);
    } else {
      tris[static_cast<std::size_t>(f)] = tris.back();
      tris.pop_back();
      bvh.erase(f);
    }
  }
  std::uniform_real_distribution<double> coord(-1, 11);
  for (int q = 0; q < 30; ++q) {
    const Eigen::Vector3d a(coord(rng), coord(rng), coord(rng) * 0.1);
    // Some segments run along an axis: their direction has zero components.
    const Eigen::Vector3d b = q % 5 == 2 ? Eigen::Vector3d(a + Eigen::Vector3d(0, coord(rng), 0))
                                         : Eigen::Vector3d(coord(rng), coord(rng), coord(rng) * 0.1);
    const double radius = q % 3 == 0 ? 0.0 : 0.05 * q;
    std::vector<int> near;
    bvh.faces_near_segment(a, q == 1 ? a : b, radius, near);
    near = sorted(near);
    EXPECT_TRUE(std::adjacent_find(near.begin(), near.end()) == near.end()) << "a face twice";
    const Eigen::Vector3d end = q == 1 ? a : b;
    for (std::size_t f = 0; f < tris.size(); ++f) {
      double nearest = INFINITY, box_gap = 0;
      Eigen::Vector3d lo = tris[f][0].cast<double>(), hi = lo;
      for (const auto& x : tris[f]) {
        lo = lo.cwiseMin(x.cast<double>());
        hi = hi.cwiseMax(x.cast<double>());
      }
      for (int i = 0; i <= 20; ++i)
        for (int j = 0; i + j <= 20; ++j) {
          const Eigen::Vector3d p = ((20 - i - j) * tris[f][0] + i * tris[f][1] + j * tris[f][2]).cast<double>() / 20;
          nearest = std::min(nearest, distance_to_segment(p, a, end));
        }
      // A face found lies within radius + its box's half diagonal of the segment.
      box_gap = distance_to_segment(0.5 * (lo + hi), a, end) - 0.5 * (hi - lo).norm();
      const bool found = std::binary_search(near.begin(), near.end(), static_cast<int>(f));
      if (nearest <= radius) {
        EXPECT_TRUE(found) << "face " << f << " at " << nearest << " of the segment, radius " << radius;
      }
      if (found) {
        EXPECT_LE(box_gap, radius + 1e-9) << f;
      }
    }
  }
}

TEST(TriangleBvh, EditsCheckTheirArguments) {
  std::mt19937 rng(3);
  mesh::TriangleBvh bvh = fresh({random_triangle(rng, 1), random_triangle(rng, 1)});
  EXPECT_THROW(bvh.replace(2, random_triangle(rng, 1)), InvalidInputError);
  EXPECT_THROW(bvh.append(random_triangle(rng, 1), -1), InvalidInputError);
  EXPECT_THROW(bvh.erase(5), InvalidInputError);
  Triangle bad = random_triangle(rng, 1);
  bad[1].x() = NAN;
  EXPECT_THROW(bvh.replace(0, bad), InvalidInputError);
  EXPECT_THROW(bvh.append(bad, 0), InvalidInputError);
  EXPECT_EQ(bvh.face_count(), 2);  // the failed append added nothing
  bvh.erase(0);
  bvh.erase(0);
  EXPECT_EQ(bvh.face_count(), 0);
  EXPECT_TRUE(bvh.segment_hits(Eigen::Vector3d(-20, -20, -20), Eigen::Vector3d(20, 20, 20)).empty());
}

// Segments through a corner of a box (into the box) or along one of its edges meet the faces
// there; rounding once let every face around the corner reject the hit (u or v just below 0).
TEST(TriangleBvh, SegmentThroughACornerOrAlongAnEdgeHitsTheFacesThere) {
  const Eigen::Vector3f lo(0.1f, 0.7f, 0.3f), size(0.9f, 1.3f, 0.7f);
  std::vector<Triangle> tris;
  const auto corner = [&](int i) {
    return Eigen::Vector3f(lo.x() + ((i & 1) ? size.x() : 0.0f), lo.y() + ((i & 2) ? size.y() : 0.0f),
                           lo.z() + ((i & 4) ? size.z() : 0.0f));
  };
  for (const auto& q : std::vector<std::array<int, 4>>{
           {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}) {
    tris.push_back({corner(q[0]), corner(q[1]), corner(q[2])});
    tris.push_back({corner(q[0]), corner(q[2]), corner(q[3])});
  }
  const mesh::TriangleBvh bvh = fresh(tris);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.05, 1);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c = corner(i).cast<double>(), centre = (lo + 0.5f * size).cast<double>();
    for (int q = 0; q < 100; ++q) {
      // Into the box's octant at this corner.
      const Eigen::Vector3d in =
          (centre - c).cwiseSign().cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
      const auto hits = bvh.segment_hits(c - 0.3 * in, c + 0.01 * in);
      ASSERT_FALSE(hits.empty()) << "corner " << i << " direction " << in.transpose();
      for (const auto& h : hits) EXPECT_NEAR(h.t, 0.3 / 0.31, 1e-6);
    }
  }
  // Along the edge from corner 0 to corner 4 (z): through both corners, lying in two faces.
  for (int q = 0; q < 50; ++q) {
    const double s = unit(rng);
    const Eigen::Vector3d a = corner(0).cast<double>(), b = corner(4).cast<double>();
    const auto hits = bvh.segment_hits(a + (a - b) * s, b + (b - a) * s);
    ASSERT_GE(hits.size(), 2u);
    EXPECT_NEAR(hits.front().t, s / (1 + 2 * s), 1e-6);
    EXPECT_NEAR(hits.back().t, (1 + s) / (1 + 2 * s), 1e-6);
  }
}

}  // namespace
