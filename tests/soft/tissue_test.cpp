// Soft tissue on the skinned surface (soft/tissue.hpp): properties, not snapshots.
#include "cgamesh/soft/tissue.hpp"

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using soft::Tissue;
using soft::TissueOptions;

anim::RiggedModel cesium() {
  static const anim::RiggedModel m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
  return m;
}

anim::RiggedModel sheet(int n) {
  anim::RiggedModel model;
  model.meshes.push_back(cgamesh_test::grid(n));
  return model;
}

surgery::LiveModel live_at_rest(anim::RiggedModel model) {
  surgery::Placement p = surgery::place(model, anim::rest_pose(model.skeleton));
  return {std::move(model), std::move(p)};
}

/// A tear of two scalpel steps across CesiumMan's chest, in place.
surgery::LiveTear chest_tear(surgery::LiveModel& live) {
  return surgery::tear(
      live, std::vector<surgery::Scalpel>{{{0.01, 0.90, 2}, {0.01, 0.90, 0.06}}, {{-0.03, 1.0, 2}, {-0.03, 1.0, 0.06}}});
}

double largest_difference(const std::vector<mesh::RowMatrixXf<3>>& a, const std::vector<mesh::RowMatrixXf<3>>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double((a[i] - b[i]).cwiseAbs().maxCoeff()));
  return worst;
}

TEST(TissueOptions, BadValuesNameTheField) {
  const auto message = [](TissueOptions o) {
    try {
      o.validate();
    } catch (const InvalidInputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  TissueOptions o;
  EXPECT_EQ(message(o), "(no error)");
  o.density = -1;
  EXPECT_NE(message(o).find("density"), std::string::npos);
  o = {};
  o.substep = 0;
  EXPECT_NE(message(o).find("substep"), std::string::npos);
  o = {};
  o.stretch_compliance = NAN;
  EXPECT_NE(message(o).find("stretch_compliance"), std::string::npos);
  o = {};
  o.pretension = 1;
  EXPECT_NE(message(o).find("pretension"), std::string::npos);
  o = {};
  o.gravity.x() = INFINITY;
  EXPECT_NE(message(o).find("gravity"), std::string::npos);
  o = {};
  o.max_particles = -1;
  EXPECT_NE(message(o).find("max_particles"), std::string::npos);
}

TEST(Tissue, NothingHappensWhenNothingHappens) {
  const anim::RiggedModel model = cesium();
  surgery::LiveModel live = live_at_rest(model);
  Tissue tissue(live);
  for (double t = 0; t <= model.clips[0].duration; t += 0.25) {
    const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], t, anim::BlendMode::format);
    tissue.step(live, pose, 0.25);
    EXPECT_EQ(largest_difference(tissue.positions(live, pose), surgery::place(model, pose).positions), 0.0) << t;
  }
  // A region with no wound, no gravity and no pre-tension stays on the skinned surface.
  TissueOptions calm;
  calm.gravity.setZero();
  calm.pretension = 0;
  Tissue still(live, calm);
  still.select(live, 0, Eigen::Vector3d(0, 1, 0), 0.3);
  ASSERT_GT(still.free_particles(), 100u);
  const anim::Pose rest = anim::rest_pose(model.skeleton);
  still.step(live, rest, 0.5);
  EXPECT_LE(largest_difference(still.positions(live, rest), live.placement().positions), 1e-6 * 1.9);
}

TEST(Tissue, MassIsConservedThroughCutsTearsAndDrills) {
  surgery::LiveModel live = live_at_rest(cesium());
  Tissue tissue(live);
  const double mass = tissue.total_mass();
  EXPECT_GT(mass, 0);
  const surgery::LiveTear tear = chest_tear(live);
  tissue.follow(live, std::span(&tear.change, 1));
  EXPECT_NEAR(tissue.total_mass(), mass, 1e-9 * mass);
  const surgery::LiveDrill drill = surgery::drill(live, {0.0, 1.3, -0.5}, {0.0, 1.3, 0.5}, 0.04);
  tissue.follow(live, drill.changes);
  EXPECT_NEAR(tissue.total_mass(), mass, 1e-9 * mass);
  const surgery::LiveCut cut = surgery::cut(live, surgery::cut_plane({0, 1, 0}, 0.5));
  tissue.follow(live, cut.changes);
  EXPECT_NEAR(tissue.total_mass(), mass, 1e-9 * mass);
  EXPECT_GT(tissue.free_particles(), 0u);
}

/// The mean distance between the two copies of each vertex of a straight tear across a flat
/// sheet, after settling with `options`.
double settled_width(TissueOptions options) {
  surgery::LiveModel live = live_at_rest(sheet(20));
  Tissue tissue(live, options);
  const surgery::LiveTear tear = surgery::tear(
      live, std::vector<surgery::Scalpel>{{{6.3, 10.4, 1}, {6.3, 10.4, -1}}, {{13.7, 10.4, 1}, {13.7, 10.4, -1}}});
  tissue.follow(live, std::span(&tear.change, 1));
  const anim::Pose rest = anim::rest_pose(live.model().skeleton);
  EXPECT_TRUE(tissue.settle(live, rest).settled);
  const auto x = tissue.positions(live, rest);
  // Copies of one path vertex start at one place.
  std::map<std::array<float, 3>, std::vector<int>> copies;
  for (const auto& [v, side] : tear.sides) {
    const auto p = live.placement().positions[0].row(v);
    copies[{p(0), p(1), p(2)}].push_back(v);
  }
  double sum = 0;
  int n = 0;
  for (const auto& [at, vs] : copies)
    if (vs.size() == 2) {
      sum += (x[0].row(vs[0]) - x[0].row(vs[1])).norm();
      ++n;
    }
  EXPECT_GT(n, 3);
  return n > 0 ? sum / n : 0;
}

// Issue #34, locality: outside the region the tissue is the skinned surface, bit for bit, while
// the wound's region moves and the clip plays.
TEST(Tissue, OutsideTheRegionPositionsAreSkinningBitForBit) {
  const anim::RiggedModel model = cesium();
  surgery::LiveModel live = live_at_rest(model);
  Tissue tissue(live);
  const surgery::LiveTear tear = chest_tear(live);
  tissue.follow(live, std::span(&tear.change, 1));
  ASSERT_GT(tissue.free_particles(), 0u);
  const mesh::RowMatrixXf<3>& placed = live.placement().positions[0];
  const Eigen::Index first = tear.change.first_new_vertex;
  // Farther than twice the default region (10 % of the diagonal, about 1.9) from every wound vertex.
  std::vector<Eigen::Index> far;
  for (Eigen::Index v = 0; v < first; ++v) {
    float nearest = INFINITY;
    for (Eigen::Index w = first; w < placed.rows(); ++w) nearest = std::min(nearest, (placed.row(v) - placed.row(w)).norm());
    if (nearest > 0.4f) far.push_back(v);
  }
  ASSERT_GT(far.size(), 1000u);
  bool moved_near = false;
  for (double t = 0; t <= model.clips[0].duration; t += 0.1) {
    const anim::Pose pose = anim::sample(live.model().skeleton, live.model().clips[0], t, anim::BlendMode::format);
    tissue.step(live, pose, 0.1);
    const auto ours = tissue.positions(live, pose);
    const auto skinned = surgery::place(live.model(), pose).positions;
    for (const Eigen::Index v : far) ASSERT_EQ(ours[0].row(v), skinned[0].row(v)) << "vertex " << v << " at t = " << t;
    moved_near |= (ours[0].bottomRows(placed.rows() - first) - skinned[0].bottomRows(placed.rows() - first))
                      .cwiseAbs()
                      .maxCoeff() > 1e-4f;
  }
  EXPECT_TRUE(moved_near) << "the wound itself is simulated";
}

TEST(Tissue, ATearInATenseSheetOpensWithTheTension) {
  TissueOptions o;
  o.gravity.setZero();
  o.pretension = 0;
  const double closed = settled_width(o);
  o.pretension = 0.1;
  const double open = settled_width(o);
  o.pretension = 0.2;
  const double wider = settled_width(o);
  EXPECT_LT(closed, 1e-6);
  EXPECT_GT(open, 0.05);
  EXPECT_GT(wider, 1.3 * open);
  // The pre-tension is a strain (links rest shorter): softer links pull the attached tissue
  // around the wound less, so it opens less.
  o.pretension = 0.1;
  o.stretch_compliance = 1e-3;
  EXPECT_LT(settled_width(o), 0.5 * open);
}

/// Tissue that holds on to nothing (attachments as loose as can be), undamped, not tense.
TissueOptions loose() {
  TissueOptions o;
  o.attachment_compliance = 1e12;
  o.damping = 0;
  o.pretension = 0;
  return o;
}

TEST(Tissue, AReleasedPieceFallsAsHalfGTSquared) {
  surgery::LiveModel live = live_at_rest(sheet(4));
  Tissue tissue(live, loose());
  tissue.select(live, 0, Eigen::Vector3d(2, 2, 0), 10);
  ASSERT_EQ(tissue.free_particles(), 25u);
  const anim::Pose rest = anim::rest_pose(live.model().skeleton);
  for (int frame = 0; frame < 45; ++frame) tissue.step(live, rest, 1.0 / 90);
  const auto x = tissue.positions(live, rest);
  const double drop = (live.placement().positions[0] - x[0]).col(1).cast<double>().mean();
  EXPECT_NEAR(drop, 0.5 * 9.81 * 0.25, 0.01 * 0.5 * 9.81 * 0.25);
}

// Issue #34: with gravity off, a released piece's momentum is conserved. The sheet falls for a
// while (momentum M·g·t), then, with gravity off, skin under tension pulls it out of shape:
// the links' corrections are internal, so the momentum stays.
TEST(Tissue, WithGravityOffAFreePieceKeepsItsMomentum) {
  surgery::LiveModel live = live_at_rest(sheet(8));
  TissueOptions o = loose();
  Tissue tissue(live, o);
  tissue.select(live, 0, Eigen::Vector3d(4, 4, 0), 100);
  const anim::Pose rest = anim::rest_pose(live.model().skeleton);
  for (int frame = 0; frame < 9; ++frame) tissue.step(live, rest, 1.0 / 90);
  const Eigen::Vector3d falling = tissue.momentum();
  EXPECT_NEAR(falling.y(), -tissue.total_mass() * 9.81 * 0.1, 0.02 * tissue.total_mass() * 9.81 * 0.1);
  o.gravity.setZero();
  o.pretension = 0.2;
  tissue.set_options(live, o);
  const auto before = tissue.positions(live, rest);
  for (int frame = 0; frame < 30; ++frame) tissue.step(live, rest, 1.0 / 90);
  EXPECT_LE((tissue.momentum() - falling).norm(), 1e-6 * falling.norm()) << tissue.momentum().transpose();
  // Not a piece at rest: the tension moved it about (besides the fall).
  const auto after = tissue.positions(live, rest);
  const Eigen::RowVector3f drift = (after[0] - before[0]).colwise().mean();
  double shape = 0;
  for (Eigen::Index v = 0; v < after[0].rows(); ++v)
    shape = std::max(shape, static_cast<double>((after[0].row(v) - before[0].row(v) - drift).norm()));
  EXPECT_GT(shape, 0.1);
}

// The budget bounds a step's cost: on a fine sheet the region keeps to max_particles (its
// balls shrunk by one factor), and the wound still opens.
TEST(Tissue, TheRegionKeepsToItsBudget) {
  surgery::LiveModel live = live_at_rest(sheet(40));
  TissueOptions o;
  o.gravity.setZero();
  o.pretension = 0.2;
  o.region_radius = 20;
  o.max_particles = 300;
  Tissue tissue(live, o);
  const surgery::LiveTear tear =
      surgery::tear(live, std::vector<surgery::Scalpel>{{{15.5, 20.5, 5}, {15.5, 20.5, -5}}, {{24.5, 20.5, 5}, {24.5, 20.5, -5}}});
  tissue.follow(live, std::span(&tear.change, 1));
  EXPECT_LE(tissue.free_particles(), 300u);
  EXPECT_GT(tissue.free_particles(), 150u);
  const anim::Pose rest = anim::rest_pose(live.model().skeleton);
  (void)tissue.settle(live, rest, 2.0);
  EXPECT_GT(largest_difference(tissue.positions(live, rest), live.placement().positions), 0.1) << "the wound opened";
  o.max_particles = 0;
  tissue.set_options(live, o);
  EXPECT_GT(tissue.free_particles(), 1000u) << "without a budget, the whole ball";
}

TEST(Tissue, TheBakedModelIsTheSimulatedSurface) {
  const anim::RiggedModel model = cesium();
  surgery::LiveModel live = live_at_rest(model);
  Tissue tissue(live);
  const surgery::LiveTear tear = chest_tear(live);
  tissue.follow(live, std::span(&tear.change, 1));
  const anim::Pose pose = anim::rest_pose(model.skeleton);
  (void)tissue.settle(live, pose, 1.0);
  const auto simulated = tissue.positions(live, pose);
  EXPECT_GT(largest_difference(simulated, live.placement().positions), 1e-3) << "the wound moved";
  const anim::RiggedModel baked = tissue.bake(live, pose);
  EXPECT_LE(largest_difference(surgery::place(baked, pose).positions, simulated), 1e-5 * 1.9);
}

TEST(Tissue, StaysStableThroughRandomSurgeryWhileTheClipPlays) {
  const anim::RiggedModel model = cesium();
  const anim::Clip& clip = model.clips[0];
  surgery::LiveModel live = live_at_rest(model);
  Tissue tissue(live);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1, 1);
  double t = 0;
  int operations = 0;
  for (int frame = 0; frame < 1000; ++frame) {  // 10 000 substeps of 1/900 s
    t += 1.0 / 90;
    const anim::Pose pose = anim::sample(model.skeleton, clip, std::fmod(t, clip.duration), anim::BlendMode::format);
    if (frame % 100 == 50) {
      // As the viewer does: the model placed in the pose shown, then the tool.
      anim::RiggedModel now = live.model();
      surgery::Placement p = surgery::place(now, pose);
      live = surgery::LiveModel(std::move(now), std::move(p));
      const Eigen::Vector3d at(0.1 * u(random), 0.9 + 0.3 * u(random), 0);
      try {
        switch (frame / 100 % 3) {
          case 0: {
            const auto r = surgery::tear(live, std::vector<surgery::Scalpel>{{at + Eigen::Vector3d(0, 0, 2), at},
                                                                            {at + Eigen::Vector3d(0.05, 0.08, 2),
                                                                             at + Eigen::Vector3d(0.05, 0.08, 0)}});
            tissue.follow(live, std::span(&r.change, 1));
            break;
          }
          case 1:
            tissue.follow(live, surgery::drill(live, at + Eigen::Vector3d(0, 0, -0.5), at + Eigen::Vector3d(0, 0, 0.5),
                                               0.03).changes);
            break;
          default:
            tissue.follow(live, surgery::cut(live, surgery::cut_plane({u(random), 1, u(random)}, at.y())).changes);
        }
        ++operations;
      } catch (const TopologyError&) {
        // The tool missed: nothing changed.
      }
    }
    tissue.step(live, pose, 1.0 / 90);
    if (frame % 50 != 0) continue;
    const auto x = tissue.positions(live, pose);
    const auto skinned = surgery::place(live.model(), pose).positions;
    for (std::size_t i = 0; i < x.size(); ++i) {
      ASSERT_TRUE(x[i].allFinite()) << frame;
      EXPECT_LE((x[i] - skinned[i]).rowwise().norm().maxCoeff(), 0.2) << "frame " << frame;
    }
  }
  EXPECT_GE(operations, 6);
  EXPECT_GT(tissue.free_particles(), 100u);
}

TEST(Tissue, OneThreadGivesTheSameBits) {
  const auto run = [] {
    surgery::LiveModel live = live_at_rest(sheet(12));
    Tissue tissue(live);
    const surgery::LiveTear tear = surgery::tear(
        live, std::vector<surgery::Scalpel>{{{3.3, 6.4, 1}, {3.3, 6.4, -1}}, {{8.7, 6.4, 1}, {8.7, 6.4, -1}}});
    tissue.follow(live, std::span(&tear.change, 1));
    const anim::Pose rest = anim::rest_pose(live.model().skeleton);
    for (int k = 0; k < 20; ++k) tissue.step(live, rest, 1.0 / 90);
    return tissue.positions(live, rest)[0];
  };
  const mesh::RowMatrixXf<3> a = run(), b = run();
  EXPECT_EQ(Eigen::MatrixXf(a), Eigen::MatrixXf(b));
}

}  // namespace
