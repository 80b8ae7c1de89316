// Surgery in place (LiveModel): the same result as the copying operations, face for face, and a
// SurfaceIndex that stays what a fresh build over the edited model gives.
#include "cgamesh/surgery/live_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cgamesh/errors.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/tear.hpp"
#include "surgery/surgery_checks.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::LiveModel;

/// Per corner: placed position, rest position, skin weights.
using Corner = std::array<float, 10>;
using FaceKey = std::array<Corner, 3>;

/// Every face of a mesh as its three corners' values, starting at the smallest corner (the
/// orientation kept), sorted: equal for two meshes with the same triangles in any vertex order.
/// With `piece`, only the faces f with piece[f] == which.
std::vector<FaceKey> face_keys(const mesh::Mesh& m, const Points& placed, const std::vector<int>& piece = {}, int which = 0) {
  std::vector<FaceKey> out;
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    if (!piece.empty() && piece[static_cast<std::size_t>(f)] != which) continue;
    FaceKey key;
    for (int k = 0; k < 3; ++k) {
      const int v = m.faces(f, k);
      Corner& c = key[static_cast<std::size_t>(k)];
      for (int j = 0; j < 3; ++j) {
        c[static_cast<std::size_t>(j)] = placed(v, j);
        c[static_cast<std::size_t>(3 + j)] = m.positions(v, j);
      }
      for (int j = 0; j < 4; ++j) c[static_cast<std::size_t>(6 + j)] = m.skin.empty() ? 0.0f : m.skin.weights(v, j);
    }
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    out.push_back(key);
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The edited BVH `have` answers as `want`, built from scratch over the same faces: the same
/// faces hit by segments and near planes through the placed points `placed`.
void expect_bvh_is_fresh(const mesh::TriangleBvh& have, const mesh::TriangleBvh& want,
                         const mesh::RowMatrixXf<3>& placed, std::mt19937& rng) {
  ASSERT_EQ(have.face_count(), want.face_count());
  for (int q = 0; q < 20; ++q) {
    const Eigen::Vector3d a = random_point_in_box(rng, placed), b = random_point_in_box(rng, placed);
    const auto got = have.segment_hits(a, b), expected = want.segment_hits(a, b);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t h = 0; h < got.size(); ++h) EXPECT_EQ(got[h].face, expected[h].face);
    const Eigen::Vector3d n = random_direction(rng);
    std::vector<int> near_have, near_want;
    have.faces_near_plane(n, n.dot(a), 1e-3 * want.diagonal(), near_have);
    want.faces_near_plane(n, n.dot(a), 1e-3 * want.diagonal(), near_want);
    std::sort(near_have.begin(), near_have.end());
    std::sort(near_want.begin(), near_want.end());
    ASSERT_EQ(near_have, near_want);
  }
}

/// The index of `live` against one built from scratch over its model: the same adjacency, and
/// the same faces hit by segments and near planes through the model.
void expect_index_is_fresh(const LiveModel& live, std::mt19937& rng) {
  const surgery::SurfaceIndex fresh = surgery::SurfaceIndex::build(live.model(), live.placement());
  for (std::size_t i = 0; i < live.model().meshes.size(); ++i) {
    const surgery::MeshIndex& have = live.index().meshes[i];
    const surgery::MeshIndex& want = fresh.meshes[i];
    ASSERT_EQ(have.weld, want.weld) << "mesh " << i;
    ASSERT_EQ(have.neighbor.size(), want.neighbor.size());
    for (std::size_t f = 0; f < have.neighbor.size(); ++f)
      ASSERT_EQ(have.neighbor[f], want.neighbor[f]) << "mesh " << i << " face " << f;
    expect_bvh_is_fresh(have.bvh, want.bvh, live.placement().positions[i], rng);
  }
}

/// The change report fits the edited mesh.
void expect_change_fits(const surgery::MeshChange& c, const mesh::Mesh& m, Eigen::Index faces_before) {
  EXPECT_EQ(c.first_new_vertex + static_cast<Eigen::Index>(c.origins.size()), m.vertex_count());
  const std::set<int> ids(c.new_faces.begin(), c.new_faces.end());
  EXPECT_EQ(ids.size(), c.new_faces.size());
  for (const int f : c.new_faces) EXPECT_LT(f, m.face_count());
  EXPECT_EQ(faces_before - c.removed_faces + static_cast<Eigen::Index>(c.new_faces.size()), m.face_count());
  for (const auto& [before, after] : c.moved_faces) {
    EXPECT_LT(after, m.face_count());
    EXPECT_FALSE(ids.contains(after));
    EXPECT_GE(before, m.face_count()) << "only faces past the end move";
  }
}

TEST(LiveModel, TearInPlaceGivesTheCopyingTearsTriangles) {
  for (const std::size_t which : {std::size_t{0}, std::size_t{2}}) {
    const Subject& s = subjects()[which];
    const double diag = model_diagonal(s);
    const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s.model, s.placement);
    std::mt19937 rng(31 + static_cast<unsigned>(which));
    int torn = 0;
    for (int i = 0; i < 8; ++i) {
      SCOPED_TRACE(s.name + " stroke " + std::to_string(i));
      const auto steps = random_stroke(s, rng, 2 + i % 3, 0.04 * diag);
      surgery::TearOptions opt;
      opt.open = i % 2 == 0 ? 0.0 : 0.003 * diag;
      opt.own_side_influences = i % 4 == 3;
      surgery::ModelTear copy;
      try {
        copy = surgery::tear(s.model, s.placement, index, steps, opt);
      } catch (const TopologyError&) {
        continue;
      }
      ++torn;
      LiveModel live(s.model, s.placement);
      const surgery::LiveTear in_place = surgery::tear(live, steps, opt);
      const auto k = static_cast<std::size_t>(copy.mesh);
      ASSERT_EQ(in_place.change.mesh, copy.mesh);
      EXPECT_EQ(in_place.path, copy.path);
      EXPECT_EQ(in_place.new_vertices, copy.new_vertices);
      EXPECT_EQ(in_place.faces_out, copy.faces_out);
      EXPECT_EQ(in_place.faces_split, copy.faces_split);
      EXPECT_EQ(static_cast<std::ptrdiff_t>(in_place.sides.size()),
                std::count_if(copy.side.begin(), copy.side.end(), [](signed char x) { return x != 0; }));
      EXPECT_EQ(face_keys(live.model().meshes[k], live.placement().positions[k]), face_keys(copy.model.meshes[k], copy.placed));
      expect_change_fits(in_place.change, live.model().meshes[k], s.model.meshes[k].face_count());
    }
    EXPECT_GE(torn, 4);
  }
}

TEST(LiveModel, SuccessiveTearsKeepTheIndexAndTheOldVertices) {
  const Subject& s = subjects()[0];
  const double diag = model_diagonal(s);
  LiveModel live(s.model, s.placement);
  std::mt19937 rng(77);
  int torn = 0;
  for (int i = 0; i < 12; ++i) {
    SCOPED_TRACE("stroke " + std::to_string(i));
    const auto steps = random_stroke(s, rng, 3, 0.05 * diag);
    surgery::TearOptions opt;
    opt.open = 0.004 * diag;
    const mesh::Mesh before = live.model().meshes[0];
    surgery::LiveTear t;
    try {
      t = surgery::tear(live, steps, opt);
    } catch (const TopologyError&) {
      // A failed tear leaves the model as it was.
      EXPECT_EQ(live.model().meshes[0].faces, before.faces);
      EXPECT_EQ(live.model().meshes[0].positions, before.positions);
      continue;
    }
    ++torn;
    const mesh::Mesh& m = live.model().meshes[0];
    expect_sane_mesh(m, "torn in place");
    expect_change_fits(t.change, m, before.face_count());
    // Old vertices keep their ids and values, except the copies the opening moved.
    std::set<int> moved;
    for (const auto& [v, side] : t.sides) moved.insert(v);
    for (Eigen::Index v = 0; v < before.vertex_count(); ++v) {
      if (moved.contains(static_cast<int>(v))) continue;
      ASSERT_EQ(m.positions.row(v), before.positions.row(v)) << v;
      ASSERT_EQ(m.skin.weights.row(v), before.skin.weights.row(v)) << v;
      ASSERT_EQ(m.skin.joints.row(v), before.skin.joints.row(v)) << v;
    }
    expect_index_is_fresh(live, rng);
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(torn, 6);
}

/// A drill through a random point of the placed surface of mesh 0, in a random direction, with
/// a radius of 0.2–3.2 % of the model's size.
struct RandomDrill {
  Eigen::Vector3d tip, base;
  double radius;
};

RandomDrill random_drill(const Subject& s, std::mt19937& rng) {
  const double diag = model_diagonal(s);
  std::uniform_real_distribution<double> u(0, 1);
  const auto& faces = s.model.meshes[0].faces;
  const Points& p = s.placement.positions[0];
  const Eigen::Index f = std::uniform_int_distribution<Eigen::Index>(0, faces.rows() - 1)(rng);
  const double b0 = 0.1 + 0.8 * u(rng), b1 = (1 - b0) * (0.1 + 0.8 * u(rng));
  const Eigen::Vector3d at = b0 * p.row(faces(f, 0)).cast<double>().transpose() +
                             b1 * p.row(faces(f, 1)).cast<double>().transpose() +
                             (1 - b0 - b1) * p.row(faces(f, 2)).cast<double>().transpose();
  const Eigen::Vector3d n = random_direction(rng);
  return {at + diag * n, at - diag * n, diag * (0.002 + 0.03 * u(rng))};
}

TEST(LiveModel, DrillInPlaceGivesTheCopyingDrillsTriangles) {
  for (const std::size_t which : {std::size_t{0}, std::size_t{2}}) {
    const Subject& s = subjects()[which];
    const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s.model, s.placement);
    std::mt19937 rng(5 + static_cast<unsigned>(which));
    for (int i = 0; i < 6; ++i) {
      SCOPED_TRACE(s.name + " drill " + std::to_string(i));
      const RandomDrill d = random_drill(s, rng);
      surgery::DrillOptions opt;
      opt.wall = i % 2 == 1;
      const surgery::ModelDrill copy = surgery::drill(s.model, s.placement, index, d.tip, d.base, d.radius, opt);
      LiveModel live(s.model, s.placement);
      const surgery::LiveDrill in_place = surgery::drill(live, d.tip, d.base, d.radius, opt);
      EXPECT_EQ(in_place.new_vertices, copy.new_vertices);
      EXPECT_EQ(in_place.faces_out, copy.faces_out);
      EXPECT_EQ(in_place.faces_removed, copy.faces_removed);
      EXPECT_EQ(in_place.intersection_points, copy.intersection_points);
      EXPECT_EQ(in_place.wall_triangles, copy.wall_triangles);
      ASSERT_EQ(in_place.changes.size(), 1u);
      ASSERT_EQ(copy.source_mesh, std::vector<int>{0});
      EXPECT_EQ(face_keys(live.model().meshes[0], live.placement().positions[0]), face_keys(copy.model.meshes[0], copy.placed[0]));
      expect_change_fits(in_place.changes[0], live.model().meshes[0], s.model.meshes[0].face_count());
    }
  }
}

TEST(LiveModel, DrillsAndTearsInTurnKeepTheIndex) {
  const Subject& s = subjects()[0];
  const double diag = model_diagonal(s);
  LiveModel live(s.model, s.placement);
  std::mt19937 rng(19);
  int done = 0;
  for (int i = 0; i < 16; ++i) {
    SCOPED_TRACE("operation " + std::to_string(i));
    const Eigen::Index faces_before = live.model().meshes[0].face_count();
    try {
      if (i % 2 == 0) {
        const RandomDrill d = random_drill(s, rng);
        surgery::DrillOptions opt;
        opt.wall = i % 4 == 0;
        const surgery::LiveDrill r = surgery::drill(live, d.tip, d.base, d.radius, opt);
        ASSERT_EQ(r.changes.size(), 1u);
        expect_change_fits(r.changes[0], live.model().meshes[0], faces_before);
      } else {
        surgery::TearOptions opt;
        opt.open = 0.004 * diag;
        const surgery::LiveTear t = surgery::tear(live, random_stroke(s, rng, 3, 0.05 * diag), opt);
        expect_change_fits(t.change, live.model().meshes[0], faces_before);
      }
    } catch (const TopologyError&) {
      continue;  // a stroke over a hole, or a drill through one
    }
    ++done;
    expect_sane_mesh(live.model().meshes[0], "after operation " + std::to_string(i));
    expect_index_is_fresh(live, rng);
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(done, 10);
}

TEST(LiveModel, ToolsThatMissChangeNothing) {
  const Subject& s = subjects()[0];
  LiveModel live(s.model, s.placement);
  const Eigen::Vector3d far = Eigen::Vector3d::Constant(100 * model_diagonal(s));
  const std::vector<surgery::Scalpel> steps{{far, far + Eigen::Vector3d::UnitX()}, {far, far + Eigen::Vector3d::UnitY()}};
  EXPECT_THROW((void)surgery::tear(live, steps), TopologyError);
  EXPECT_THROW((void)surgery::drill(live, far, far + Eigen::Vector3d::UnitX(), 0.1), TopologyError);
  EXPECT_THROW((void)surgery::drill(live, far, far, 0.1), InvalidInputError);
  EXPECT_EQ(live.model().meshes[0].faces, s.model.meshes[0].faces);
  EXPECT_EQ(live.placement().positions[0], s.placement.positions[0]);
}

/// Piece of every face of mesh i after a cut in place: new faces as reported, the others by the
/// side of their vertices (all off the plane).
std::vector<int> pieces_after(const LiveModel& live, std::size_t i, const surgery::LiveCut& c, const Eigen::Vector3d& n, double d) {
  const mesh::Mesh& m = live.model().meshes[i];
  const Points& p = live.placement().positions[i];
  std::vector<int> out(static_cast<std::size_t>(m.face_count()), -1);
  for (std::size_t k = 0; k < c.changes.size(); ++k)
    if (c.changes[k].mesh == static_cast<int>(i))
      for (std::size_t j = 0; j < c.changes[k].new_faces.size(); ++j)
        out[static_cast<std::size_t>(c.changes[k].new_faces[j])] = c.piece_of_new_face[k][j];
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    if (out[static_cast<std::size_t>(f)] >= 0) continue;
    double far = 0;
    for (int k = 0; k < 3; ++k) {
      const double x = n.dot(p.row(m.faces(f, k)).cast<double>().transpose()) - d;
      if (std::abs(x) > std::abs(far)) far = x;
    }
    out[static_cast<std::size_t>(f)] = far > 0 ? 0 : 1;
  }
  return out;
}

TEST(LiveModel, CutInPlaceSeparatesThePiecesOfTheCopyingCut) {
  for (std::size_t which = 0; which < subjects().size(); ++which) {
    const Subject& s = subjects()[which];
    std::mt19937 rng(101 + static_cast<unsigned>(which));
    int separated = 0;
    for (int i = 0; i < 8; ++i) {
      SCOPED_TRACE(s.name + " plane " + std::to_string(i));
      const Eigen::Vector3d n = random_direction(rng);
      const double d = n.dot(random_point_in_box(rng, s.placement.positions[0]));
      const cga::Vector<double> plane = cga::plane(n, d);
      surgery::CutOptions opt;
      opt.own_side_influences = i % 3 == 2;
      opt.predicates = i % 2 == 0 ? surgery::Predicates::cga : surgery::Predicates::euclidean;
      surgery::ModelCut copy;
      try {
        copy = surgery::cut(s.model, s.placement, plane, opt);
      } catch (const TopologyError&) {
        LiveModel live(s.model, s.placement);
        EXPECT_THROW((void)surgery::cut(live, plane, opt), TopologyError);
        continue;
      }
      if (copy.faces_split == 0) continue;
      ++separated;
      LiveModel live(s.model, s.placement);
      const surgery::LiveCut c = surgery::cut(live, plane, opt);
      EXPECT_EQ(c.faces_split, copy.faces_split);
      EXPECT_EQ(c.intersection_points, copy.intersection_points);
      EXPECT_EQ(c.faces_out, copy.faces_out[0] + copy.faces_out[1]);
      ASSERT_EQ(c.changes.size(), c.piece_of_new_face.size());
      for (std::size_t k = 0; k < c.changes.size(); ++k) {
        const auto i_mesh = static_cast<std::size_t>(c.changes[k].mesh);
        expect_change_fits(c.changes[k], live.model().meshes[i_mesh], s.model.meshes[i_mesh].face_count());
        EXPECT_EQ(c.changes[k].new_faces.size(), c.piece_of_new_face[k].size());
      }
      for (std::size_t m = 0; m < s.model.meshes.size(); ++m) {
        const std::vector<int> piece = pieces_after(live, m, c, n, d);
        const mesh::Mesh& edited = live.model().meshes[m];
        for (int p = 0; p < 2; ++p) {
          const auto& sources = copy.source_mesh[static_cast<std::size_t>(p)];
          const auto at = std::find(sources.begin(), sources.end(), static_cast<int>(m));
          const std::vector<FaceKey> have = face_keys(edited, live.placement().positions[m], piece, p);
          if (at == sources.end()) {
            EXPECT_TRUE(have.empty());
            continue;
          }
          const auto j = static_cast<std::size_t>(at - sources.begin());
          EXPECT_EQ(have, face_keys(copy.pieces[static_cast<std::size_t>(p)].meshes[j], copy.placed[static_cast<std::size_t>(p)][j]))
              << "mesh " << m << " piece " << p;
        }
        // The pieces are apart in the index: no face is next to a face of the other piece, and
        // within a piece the adjacency is that of a fresh index.
        const surgery::SurfaceIndex fresh = surgery::SurfaceIndex::build(live.model(), live.placement());
        const auto& have = live.index().meshes[m].neighbor;
        const auto& want = fresh.meshes[m].neighbor;
        ASSERT_EQ(have.size(), want.size());
        for (std::size_t f = 0; f < have.size(); ++f)
          for (std::size_t k = 0; k < 3; ++k) {
            const int g = want[f][k];
            const bool across = g >= 0 && piece[f] != piece[static_cast<std::size_t>(g)];
            ASSERT_EQ(have[f][k], across ? -1 : g) << "mesh " << m << " face " << f << " edge " << k;
          }
        expect_bvh_is_fresh(live.index().meshes[m].bvh, fresh.meshes[m].bvh, live.placement().positions[m], rng);
      }
      if (HasFatalFailure()) return;
    }
    EXPECT_GE(separated, 3) << s.name;
  }
}

TEST(LiveModel, CutInPlaceRejectsMissesTouchesAndCaps) {
  const Subject& s = subjects()[0];
  LiveModel live(s.model, s.placement);
  const Points& p = s.placement.positions[0];
  const double top = p.col(1).maxCoeff();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  surgery::CutOptions cap;
  cap.cap = true;
  EXPECT_THROW((void)surgery::cut(live, cga::plane(up, 0.5 * top), cap), InvalidInputError);
  EXPECT_THROW((void)surgery::cut(live, cga::plane(up, 2.0 * top + 1), {}), TopologyError);
  // The horizontal plane through the highest vertex touches the model there only.
  EXPECT_THROW((void)surgery::cut(live, cga::plane(up, top), {}), TopologyError);
  EXPECT_EQ(live.model().meshes[0].faces, s.model.meshes[0].faces);
}

}  // namespace
