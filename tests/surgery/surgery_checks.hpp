#pragma once
// Invariants every surgery result must satisfy, shared by the cut, tear and drill tests.

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh_test {

/// Fewer random cases in the (slow) sanitizer build.
#ifdef CGAMESH_SANITIZED
inline constexpr int kCaseScale = 1;
#else
inline constexpr int kCaseScale = 10;
#endif

using Faces = cgamesh::mesh::Faces;
using Points = cgamesh::mesh::RowMatrixXf<3>;

using cgamesh::mesh::weld_by_position;

/// Vertex ids of a surgery result welded through their origins: vertices made from the same
/// welded old vertices (seam copies, cap copies, the two sides of a crossing) share one id.
/// Exact even where the two copies' parameters differ in the last bit.
inline std::vector<int> weld_origins(const std::vector<cgamesh::mesh::VertexSource>& origins,
                                     const std::vector<int>& old_weld) {
  std::map<std::array<int, 3>, int> first;
  std::vector<int> out(origins.size());
  for (std::size_t i = 0; i < origins.size(); ++i) {
    std::array<int, 3> key{-1, -1, -1};
    for (int k = 0; k < origins[i].count(); ++k)
      key[static_cast<std::size_t>(k)] =
          old_weld[static_cast<std::size_t>(origins[i].vertex[static_cast<std::size_t>(k)])];
    std::sort(key.begin(), key.end());
    out[i] = first.try_emplace(key, static_cast<int>(i)).first->second;
  }
  return out;
}

/// Vertex ids of a surgery result welded through their origins by welded old vertices and
/// weights (rounded to 1e-5, so both sides of a seam, whose parameters may differ in the last
/// bit, agree): distinct points of one edge or face stay apart, unlike weld_origins.
inline std::vector<int> weld_points(const std::vector<cgamesh::mesh::VertexSource>& origins,
                                    const std::vector<int>& old_weld) {
  std::map<std::array<std::pair<int, long long>, 3>, int> first;
  std::vector<int> out;
  out.reserve(origins.size());
  for (const cgamesh::mesh::VertexSource& o : origins) {
    std::array<std::pair<int, long long>, 3> key{};
    for (std::size_t j = 0; j < 3; ++j)
      key[j] = o.vertex[j] < 0 ? std::pair<int, long long>{-1, 0}
                               : std::pair<int, long long>{old_weld[static_cast<std::size_t>(o.vertex[j])],
                                                           std::llround(1e5 * static_cast<double>(o.weight[j]))};
    std::sort(key.begin(), key.end());
    out.push_back(first.try_emplace(key, static_cast<int>(out.size())).first->second);
  }
  return out;
}

/// Directed welded edges and their multiplicity.
inline std::map<std::pair<int, int>, int> directed_edges(const Faces& f, const std::vector<int>& w) {
  std::map<std::pair<int, int>, int> e;
  for (Eigen::Index i = 0; i < f.rows(); ++i)
    for (int k = 0; k < 3; ++k)
      ++e[{w[static_cast<std::size_t>(f(i, k))], w[static_cast<std::size_t>(f(i, (k + 1) % 3))]}];
  return e;
}

/// Directed welded edges with no reverse twin (the boundary, oriented by its faces).
inline std::vector<std::pair<int, int>> boundary_edges(const Faces& f, const std::vector<int>& w) {
  const auto e = directed_edges(f, w);
  std::vector<std::pair<int, int>> out;
  for (const auto& [key, n] : e)
    if (!e.contains({key.second, key.first})) out.push_back(key);
  return out;
}

/// Closed and consistently oriented: every welded directed edge is matched by as many reverse
/// edges (twice each where a plane touches the surface along an edge: a pinch, still closed).
inline bool closed_and_oriented(const Faces& f, const std::vector<int>& w) {
  const auto e = directed_edges(f, w);
  for (const auto& [key, n] : e) {
    const auto twin = e.find({key.second, key.first});
    if (twin == e.end() || twin->second != n) return false;
  }
  return true;
}

inline bool closed_and_oriented(const Faces& f, const Points& p) { return closed_and_oriented(f, weld_by_position(p)); }

/// Boundary edges form closed loops: at every vertex as many leave as arrive.
inline bool boundary_is_loops(const std::vector<std::pair<int, int>>& edges) {
  std::map<int, int> balance;
  for (const auto& [a, b] : edges) {
    ++balance[a];
    --balance[b];
  }
  for (const auto& [v, n] : balance)
    if (n != 0) return false;
  return true;
}

inline double area(const Faces& f, const Points& p) {
  double sum = 0;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const Eigen::Vector3d a = p.row(f(i, 0)).cast<double>(), b = p.row(f(i, 1)).cast<double>(),
                          c = p.row(f(i, 2)).cast<double>();
    sum += 0.5 * (b - a).cross(c - a).norm();
  }
  return sum;
}

/// Signed volume enclosed by a closed oriented surface (divergence theorem).
inline double volume(const Faces& f, const Points& p) {
  double sum = 0;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const Eigen::Vector3d a = p.row(f(i, 0)).cast<double>(), b = p.row(f(i, 1)).cast<double>(),
                          c = p.row(f(i, 2)).cast<double>();
    sum += a.dot(b.cross(c)) / 6.0;
  }
  return sum;
}

inline double diagonal(const Points& p) {
  return static_cast<double>((p.colwise().maxCoeff() - p.colwise().minCoeff()).norm());
}

/// No NaN anywhere; every skinned vertex has at most 4 influences, >= 0, summing to 1.
inline void expect_sane_mesh(const cgamesh::mesh::Mesh& m, const std::string& what) {
  EXPECT_TRUE(m.positions.allFinite()) << what;
  EXPECT_TRUE(m.normals.allFinite()) << what;
  EXPECT_TRUE(m.uvs.allFinite()) << what;
  if (m.face_count() > 0) {
    EXPECT_GE(m.faces.minCoeff(), 0) << what;
    EXPECT_LT(m.faces.maxCoeff(), m.vertex_count()) << what;
  }
  if (m.skin.empty()) return;
  ASSERT_EQ(m.skin.weights.rows(), m.vertex_count()) << what;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const auto w = m.skin.weights.row(v);
    EXPECT_GE(w.minCoeff(), 0.0f) << what << " vertex " << v;
    EXPECT_NEAR(w.sum(), 1.0f, 1e-5f) << what << " vertex " << v;
    for (int k = 0; k < 4; ++k) EXPECT_LT(m.skin.joints(v, k), m.skin.palette.size()) << what << " vertex " << v;
  }
}

/// World positions of a mesh of `model` in clip 0 at `time` (the bind pose without clips).
inline Points skinned(const cgamesh::anim::RiggedModel& model, const cgamesh::mesh::Mesh& m, double time) {
  using namespace cgamesh;
  const anim::Pose pose = model.clips.empty()
                              ? anim::rest_pose(model.skeleton)
                              : anim::sample(model.skeleton, model.clips[0], time, anim::BlendMode::format);
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  return anim::skin(m, anim::make_palette(m, gv, gm, anim::SkinningMode::cga, anim::morph_weights(pose, m)), 1);
}

/// Key of a vertex origin: the same point of the input surface gives the same key.
inline std::array<float, 6> origin_key(const cgamesh::mesh::VertexSource& s) {
  std::array<std::pair<int, float>, 3> slots{};
  for (std::size_t k = 0; k < 3; ++k) slots[k] = {s.vertex[k], s.weight[k]};
  std::sort(slots.begin(), slots.end());
  return {static_cast<float>(slots[0].first), slots[0].second, static_cast<float>(slots[1].first), slots[1].second,
          static_cast<float>(slots[2].first), slots[2].second};
}

/// Re-animating a result of local surgery on mesh `src` of `before`: at each time, every copied
/// old vertex moves exactly as in the untouched model, and vertices made from the same point of
/// the input surface (seam and tear copies) move together, so no seam cracks.
inline void expect_reanimates_like(const cgamesh::anim::RiggedModel& before, std::size_t src,
                                   const cgamesh::anim::RiggedModel& after, std::size_t dst,
                                   const std::vector<cgamesh::mesh::VertexSource>& origins, double tolerance,
                                   const Points* placed = nullptr) {
  const cgamesh::mesh::Mesh& m = after.meshes[dst];
  for (double t : {0.3, 1.1}) {
    const Points now = skinned(after, m, t);
    const Points old = skinned(before, before.meshes[src], t);
    // Copies of one point: one origin and (when given) one placed position; a drill's blind
    // hole has points off the surface that take the influences of the rim point above them.
    std::map<std::array<float, 9>, Eigen::Vector3f> seen;
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const cgamesh::mesh::VertexSource& o = origins[static_cast<std::size_t>(v)];
      if (o.count() == 1) {
        ASSERT_LE((now.row(v) - old.row(o.vertex[0])).norm(), tolerance) << "old vertex " << o.vertex[0] << " t=" << t;
        continue;
      }
      const auto o6 = origin_key(o);
      std::array<float, 9> key{o6[0], o6[1], o6[2], o6[3], o6[4], o6[5], 0, 0, 0};
      if (placed != nullptr)
        for (int c = 0; c < 3; ++c) key[static_cast<std::size_t>(6 + c)] = (*placed)(v, c);
      const auto [it, added] = seen.try_emplace(key, now.row(v).transpose());
      if (!added) {
        ASSERT_LE((it->second - now.row(v).transpose()).norm(), tolerance) << "copies of a new vertex part, t=" << t;
      }
    }
  }
}

/// Uniform random unit vector.
inline Eigen::Vector3d random_direction(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::Vector3d n(g(rng), g(rng), g(rng));
  return n.normalized();
}

/// Uniform random point of the bounding box of `p`.
inline Eigen::Vector3d random_point_in_box(std::mt19937& rng, const Points& p) {
  std::uniform_real_distribution<double> u(0, 1);
  const Eigen::Vector3d lo = p.colwise().minCoeff().cast<double>(), hi = p.colwise().maxCoeff().cast<double>();
  return lo + (hi - lo).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
}

}  // namespace cgamesh_test
