// The editing session behind the viewer: animation state, surgery with undo and redo, strokes,
// picking, keyframes and scripts, headless.
#include "cgamesh/session/session.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/mesh_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/session/script.hpp"
#include "cgamesh/surgery/pieces.hpp"
#include "cgamesh/surgery/placement.hpp"

#include "anim/model_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using cgamesh::InvalidInputError;
using cgamesh::TopologyError;
using cgamesh::session::Session;

cgamesh::anim::RiggedModel cesium() {
  static const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
  return m;
}

long faces(const Session& s) {
  long n = 0;
  for (const auto& m : s.model().meshes) n += m.face_count();
  return n;
}

long vertices(const Session& s) {
  long n = 0;
  for (const auto& m : s.model().meshes) n += m.vertex_count();
  return n;
}

TEST(Session, UndoAndRedoGoThroughEveryOperation) {
  Session s(cesium());
  s.set_clip(0);
  s.set_time(0.5);
  const long f0 = faces(s);
  EXPECT_FALSE(s.can_undo());
  const auto cut = s.cut({0, 1, 0}, 0.9);
  EXPECT_EQ(cut.kind, "cut");
  EXPECT_GT(cut.placement_milliseconds, 0);
  const long f1 = faces(s);
  EXPECT_GT(f1, f0);
  const auto drill = s.drill({0, 1.3, -0.05}, {0, 1.3, 0.3}, 0.04);
  EXPECT_EQ(drill.placement_milliseconds, 0);  // same pose: placed once
  const long f2 = faces(s);
  EXPECT_NE(f2, f1);
  EXPECT_TRUE(s.undo());
  EXPECT_EQ(faces(s), f1);
  EXPECT_TRUE(s.undo());
  EXPECT_EQ(faces(s), f0);
  EXPECT_FALSE(s.undo());
  EXPECT_TRUE(s.redo());
  EXPECT_TRUE(s.redo());
  EXPECT_EQ(faces(s), f2);
  EXPECT_FALSE(s.redo());
  s.reset();
  EXPECT_EQ(faces(s), f0);
  EXPECT_FALSE(s.can_undo());
}

TEST(Session, TheIndexTellsThePiecesOfACutInPlaceApart) {
  Session s(cesium());
  (void)s.cut({0, 1, 0}, 0.9);
  const auto& m = s.model().meshes[0];
  // Both sides share rest positions along the cut: welded by position they are one piece.
  EXPECT_EQ(cgamesh::surgery::pieces(m).count, 1);
  const auto apart = cgamesh::surgery::pieces(m, s.index().meshes[0].weld);
  EXPECT_GE(apart.count, 2);
  // Every piece lies on one side of the plane.
  const auto placed = cgamesh::surgery::place(s.model(), s.pose()).positions[0];
  std::vector<int> side(static_cast<std::size_t>(apart.count), 0);
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const int piece = apart.of_vertex[static_cast<std::size_t>(m.faces(f, 0))];
    const double y = (placed.row(m.faces(f, 0)) + placed.row(m.faces(f, 1)) + placed.row(m.faces(f, 2))).y() / 3;
    const int here = y > 0.9 ? 1 : -1;
    int& seen = side[static_cast<std::size_t>(piece)];
    if (seen == 0) seen = here;
    ASSERT_EQ(seen, here) << "face " << f << " of piece " << piece;
  }
  EXPECT_NE(std::find(side.begin(), side.end(), 1), side.end());
  EXPECT_NE(std::find(side.begin(), side.end(), -1), side.end());
  EXPECT_THROW((void)cgamesh::surgery::pieces(m, std::vector<int>(3, 0)), InvalidInputError);
}

TEST(Session, AFailedOperationChangesNothingAndLeavesNoUndoStep) {
  Session s(cesium());
  EXPECT_THROW((void)s.cut({0, 1, 0}, 100), TopologyError);
  EXPECT_THROW((void)s.cut({0, 0, 0}, 1), InvalidInputError);
  EXPECT_FALSE(s.can_undo());
  EXPECT_EQ(faces(s), cesium().meshes[0].face_count());
}

TEST(Session, ACappedCutKeepsBothClosedPiecesAsMeshes) {
  Session s(cesium());
  cgamesh::surgery::CutOptions o;
  o.cap = true;
  const auto r = s.cut({0, 1, 0}, 0.9, o);
  EXPECT_EQ(s.model().meshes.size(), 2u);
  EXPECT_NE(r.command.find("--cap"), std::string::npos);
  EXPECT_EQ(s.model().clips.size(), cesium().clips.size());
  EXPECT_TRUE(s.undo());
  EXPECT_EQ(s.model().meshes.size(), 1u);
}

// Issue #33 item 7: the replay commands chain (each acts on the file the one before wrote, an
// undone step's on what the model shown came from) and print numbers in their shortest exact form.
TEST(Session, ReplayCommandsChainAndPrintShortestNumbers) {
  cgamesh::session::SessionOptions options;
  options.model_file = "in put.glb";
  Session s(cesium(), options);
  const auto cut = s.cut({0, 1, 0}, 0.9);
  EXPECT_EQ(cut.command, "cut 'in put.glb' --plane 0,1,0,0.9 -o step1.glb");
  s.set_clip(0);
  s.set_time(0.5);
  const auto drill = s.drill({0.0, 1.3, -0.05}, {0.0, 1.3, 0.3}, 0.04);
  EXPECT_EQ(drill.command,
            "drill step1.glb --anim 0 --time 0.5 --blend format --tip 0,1.3,-0.05 --base 0,1.3,0.3 --radius 0.04 -o "
            "step2.glb");
  ASSERT_TRUE(s.undo());
  const auto tear = s.tear(std::vector<cgamesh::surgery::Scalpel>{{{0.01, 0.90, 2}, {0.01, 0.90, 0.06}},
                                                                  {{-0.005, 0.93, 2}, {-0.005, 0.93, 0.06}}});
  EXPECT_EQ(tear.command.substr(0, 16), "tear step1.glb -") << tear.command;
  EXPECT_TRUE(tear.command.ends_with(" -o step3.glb")) << tear.command;
  EXPECT_NE(tear.command.find("--scalpel 0.01,0.9,2,0.01,0.9,0.06 --scalpel -0.005,0.93,2,-0.005,0.93,0.06"),
            std::string::npos)
      << tear.command;
  s.reset();
  EXPECT_TRUE(s.cut({0, 1, 0}, 0.9).command.starts_with("cut 'in put.glb' ")) << "reset: back to the file";
}

TEST(Session, AStrokeEndsAsTheTearOverAllItsSteps) {
  // The README's tear of CesiumMan at t = 0.5.
  const std::vector<cgamesh::surgery::Scalpel> blades{{{0.01, 0.90, 2}, {0.01, 0.90, 0.06}},
                                                      {{-0.005, 0.93, 2}, {-0.005, 0.93, 0.06}},
                                                      {{-0.02, 0.96, 2}, {-0.02, 0.96, 0.06}}};
  Session once(cesium());
  once.set_clip(0);
  once.set_time(0.5);
  const auto whole = once.tear(blades);
  Session dragged(cesium());
  dragged.set_clip(0);
  dragged.set_time(0.5);
  dragged.begin_stroke();
  EXPECT_TRUE(dragged.stroking());
  EXPECT_FALSE(dragged.can_undo());  // not in the middle of a stroke
  for (const auto& b : blades) (void)dragged.stroke_step(b);
  const auto end = dragged.end_stroke();
  ASSERT_TRUE(end.has_value());
  EXPECT_FALSE(dragged.stroking());
  EXPECT_EQ(end->command, whole.command);
  EXPECT_EQ(faces(dragged), faces(once));
  ASSERT_EQ(vertices(dragged), vertices(once));
  EXPECT_TRUE(dragged.model().meshes[0].positions.isApprox(once.model().meshes[0].positions, 1e-6));
  EXPECT_TRUE(dragged.undo());  // the whole stroke is one step
  EXPECT_EQ(faces(dragged), cesium().meshes[0].face_count());
  // A stroke of one position changes nothing.
  dragged.begin_stroke();
  (void)dragged.stroke_step(blades[0]);
  EXPECT_FALSE(dragged.end_stroke().has_value());
  EXPECT_EQ(faces(dragged), cesium().meshes[0].face_count());
}

// Issue #34 in the viewer's session: the tissue follows every in-place operation and a stroke
// step by step; the wound opens while the clip plays; Bake is one undo step; undo, redo and a
// model replaced keep the tissue on or off as the user set it.
TEST(Session, TheTissueOpensADraggedTearWhileTheClipPlaysAndBakesAsOneUndoStep) {
  const std::vector<cgamesh::surgery::Scalpel> blades{{{0.01, 0.90, 2}, {0.01, 0.90, 0.06}},
                                                      {{-0.005, 0.93, 2}, {-0.005, 0.93, 0.06}},
                                                      {{-0.02, 0.96, 2}, {-0.02, 0.96, 0.06}}};
  Session s(cesium());
  s.set_clip(0);
  s.set_time(0.5);
  cgamesh::soft::TissueOptions o;
  o.gravity.setZero();
  o.pretension = 0.2;
  s.set_tissue(o);
  ASSERT_NE(s.tissue(), nullptr);
  EXPECT_EQ(s.tissue()->free_particles(), 0u);
  s.begin_stroke();
  for (const auto& b : blades) {
    (void)s.stroke_step(b);
    EXPECT_GE(s.step_tissue(1.0 / 90), 0.0);
  }
  EXPECT_GT(s.tissue()->free_particles(), 0u) << "the tissue followed the steps";
  ASSERT_TRUE(s.end_stroke().has_value());
  const std::size_t wound = s.tissue()->free_particles();
  EXPECT_GT(wound, 0u);
  // He walks on while the wound opens: simulated near it, skinned (exactly) elsewhere.
  const auto first_new = static_cast<Eigen::Index>(cesium().meshes[0].vertex_count());
  for (int frame = 0; frame < 45; ++frame) {
    s.set_time(0.5 + frame / 90.0);
    (void)s.step_tissue(1.0 / 90);
  }
  const auto simulated = s.tissue_positions();
  const auto skinned = cgamesh::surgery::place(s.model(), s.pose()).positions;
  double opened = 0;
  for (Eigen::Index v = first_new; v < simulated[0].rows(); ++v)
    opened = std::max(opened, static_cast<double>((simulated[0].row(v) - skinned[0].row(v)).norm()));
  EXPECT_GT(opened, 5e-3) << "the wound opened (model units: metres)";
  Eigen::Index top = 0;
  (void)skinned[0].col(1).maxCoeff(&top);
  EXPECT_LT((simulated[0].row(top) - skinned[0].row(top)).norm(), 1e-6) << "the top of the head is far from the chest";
  // Bake: one undo step; the wound is in the model's rest shape.
  const long before = faces(s);
  const auto baked = s.bake_tissue();
  EXPECT_EQ(baked.kind, "bake tissue");
  EXPECT_EQ(faces(s), before);
  const auto after_bake = cgamesh::surgery::place(s.model(), s.pose()).positions;
  EXPECT_LE((after_bake[0] - simulated[0]).cwiseAbs().maxCoeff(), 1e-5 * 1.9);
  EXPECT_EQ(s.tissue()->free_particles(), 0u) << "afresh on the baked model";
  ASSERT_TRUE(s.undo());
  EXPECT_EQ(s.tissue()->free_particles(), wound) << "the tissue as it was before the bake";
  EXPECT_TRUE(s.redo());
  // Off stays off through undo; on again starts afresh.
  s.set_tissue(std::nullopt);
  EXPECT_EQ(s.tissue(), nullptr);
  ASSERT_TRUE(s.undo());
  EXPECT_EQ(s.tissue(), nullptr);
  EXPECT_THROW((void)s.bake_tissue(), InvalidInputError);
  s.set_tissue(o);
  (void)s.drill({0, 1.3, -0.5}, {0, 1.3, 0.5}, 0.04);
  EXPECT_GT(s.tissue()->free_particles(), 0u) << "a drill's wound";
  cgamesh::surgery::CutOptions capped;
  capped.cap = true;
  (void)s.cut({0, 1, 0}, 0.9, capped);
  EXPECT_EQ(s.tissue()->free_particles(), 0u) << "a capped cut replaces the model: the tissue starts afresh";
  o.pretension = 1;
  EXPECT_THROW(s.set_tissue(o), InvalidInputError);
  EXPECT_DOUBLE_EQ(s.tissue()->options().pretension, 0.2);
}

TEST(Session, PickFindsTheFirstSurfaceOnTheRayAndItsJoint) {
  Session s(cesium());
  s.set_clip(0);
  s.set_time(0.3);
  const auto& m = s.model().meshes[0];
  const auto placed = cgamesh::surgery::place(s.model(), s.pose()).positions[0];
  int tested = 0;
  for (Eigen::Index f = 0; f < m.face_count(); f += 97) {
    const Eigen::Vector3d a = placed.row(m.faces(f, 0)).cast<double>(), b = placed.row(m.faces(f, 1)).cast<double>(),
                          c = placed.row(m.faces(f, 2)).cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    const Eigen::Vector3d centre = (a + b + c) / 3, origin = centre + n.normalized() * 3;
    const auto hit = s.pick(origin, centre - origin);
    ASSERT_TRUE(hit.has_value());
    // Nothing lies beyond the face's centre along the ray.
    EXPECT_LE((hit->point - origin).norm(), 3 + 1e-6);
    EXPECT_LE(hit->normal.dot(centre - origin), 0);
    EXPECT_GE(hit->joint, 0);
    ++tested;
  }
  EXPECT_GT(tested, 20);
  EXPECT_FALSE(s.pick({0, 100, 0}, {0, 1, 0}).has_value());
  EXPECT_THROW((void)s.pick({0, 0, 0}, {0, 0, 0}), InvalidInputError);
}

TEST(Session, KeysGenerateAClipThatUndoRemoves) {
  Session s(cesium());
  const std::size_t clips = s.model().clips.size();
  cgamesh::anim::JointEdit e;
  e.joint = 3;
  e.axis = {0, 0, 1};
  s.set_time(0);
  s.add_key();
  e.angle = 0.8;
  s.set_edit(e);
  s.set_time(1);
  s.add_key();
  EXPECT_EQ(s.keys().size(), 2u);
  EXPECT_THROW(s.generate_clip(""), InvalidInputError);  // generate_clip refuses an empty name
  s.generate_clip("wave");
  EXPECT_EQ(s.model().clips.size(), clips + 1);
  EXPECT_EQ(s.clip(), static_cast<int>(clips));
  EXPECT_TRUE(s.edits().empty());
  EXPECT_TRUE(s.undo());
  EXPECT_EQ(s.model().clips.size(), clips);
  EXPECT_EQ(s.clip(), -1);
}

TEST(Session, BadEditsAndTimesAreRefused) {
  Session s(cesium());
  cgamesh::anim::JointEdit e;
  e.joint = 1000;
  EXPECT_THROW(s.set_edit(e), InvalidInputError);
  e.joint = 0;
  e.axis = {0, 0, 0};
  EXPECT_THROW(s.set_edit(e), InvalidInputError);
  e.axis = {0, 0, 1};
  e.scale = 0;
  EXPECT_THROW(s.set_edit(e), InvalidInputError);
  EXPECT_THROW(s.set_time(-1), InvalidInputError);
  EXPECT_THROW(s.set_time(NAN), InvalidInputError);
  EXPECT_THROW(s.set_clip(99), InvalidInputError);
  EXPECT_THROW(s.save("out.txt"), InvalidInputError);
}

TEST(Session, MorphWeightsSetByNameGoIntoThePoseTheReplayAndScripts) {
  using namespace cgamesh;
  Session s(io::load_model(cgamesh_test::asset("rigged_simple_morph.glb")));
  s.set_clip(0);
  s.set_time(0.6);
  const float clip_bulge = anim::morph_weights(s.pose(), s.model().meshes[0])[0];
  s.set_morph_weight("tip", 0.75f);
  const std::vector<float> expected{clip_bulge, 0.75f};
  const anim::Pose pose = s.pose();
  const std::span<const float> w = anim::morph_weights(pose, s.model().meshes[0]);
  EXPECT_EQ(std::vector<float>(w.begin(), w.end()), expected);
  EXPECT_THROW(s.set_morph_weight("smile", 1), InvalidInputError);
  EXPECT_THROW(s.set_morph_weight("tip", NAN), InvalidInputError);
  EXPECT_EQ(s.morph_settings().size(), 1u) << "a refused weight changes nothing";
  // The replay command sets the same weight, and the pose survives an operation.
  const auto cut = s.cut({0, 1, 0}, 0.5);
  EXPECT_NE(cut.command.find(" --morph tip=0.75 "), std::string::npos) << cut.command;
  EXPECT_EQ(anim::morph_weights(s.pose(), s.model().meshes[0])[1], 0.75f);
  s.clear_morph_weights();
  EXPECT_EQ(anim::morph_weights(s.pose(), s.model().meshes[0])[1],
            anim::morph_weights(anim::sample(s.model().skeleton, s.model().clips[0], 0.6, anim::BlendMode::format),
                                s.model().meshes[0])[1]);
  // Scripts: morph TARGET=W and unmorph.
  const auto actions = session::parse_script("morph tip=0.25\nmorph bulge=-1\nunmorph\n", "test");
  ASSERT_EQ(actions.size(), 3u);
  (void)session::apply(s, actions[0]);
  (void)session::apply(s, actions[1]);
  EXPECT_EQ(s.morph_settings().size(), 2u);
  (void)session::apply(s, actions[2]);
  EXPECT_TRUE(s.morph_settings().empty());
  EXPECT_THROW((void)session::parse_script("morph tip\n", "test"), InvalidInputError);
  EXPECT_THROW((void)session::parse_script("morph tip=x\n", "test"), InvalidInputError);
}

TEST(Session, SavesThePoseWithSkinnedNormals) {
  // .obj/.ply: the frame as posed now, positions and normals skinned in the mode asked for.
  cgamesh_test::TempDir dir;
  Session s(cesium());
  s.set_clip(0);
  s.set_time(0.5);
  for (const char* name : {"now.obj", "now.ply"}) {
    SCOPED_TRACE(name);
    s.save(dir.path() / name, cgamesh::anim::SkinningMode::dqs);
    const cgamesh::io::PosedFrame frame =
        cgamesh::io::posed_frame(s.model(), s.pose(), cgamesh::anim::SkinningMode::dqs);
    const std::string expected =
        cgamesh::io::encode_mesh(s.model().meshes, frame.positions, dir.path() / name, frame.normals).bytes;
    std::ifstream in(dir.path() / name, std::ios::binary);
    const std::string written{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_TRUE(written == expected);
    EXPECT_NE(written.find(name[4] == 'o' ? "\nvn " : "property float nx\n"), std::string::npos);
  }
}

TEST(Script, ParsesEveryActionAndNamesTheLineOfABadOne) {
  const auto actions = cgamesh::session::parse_script(
      "# comment\nclip 0\n\ntime 0.5  # trailing\ncut 0,1,0,0.9 cap\ntear 0,1,1,0,1,0 1,1,1,1,1,0 open=0.01\n"
      "drag 10,20 30,40\ndrill 0,1,0 0,1,1 0.05 wall\nsave \"a b.glb\"\njoint Torso:rotate=0,0,1,30\nquit\n",
      "s.txt");
  ASSERT_EQ(actions.size(), 9u);
  EXPECT_EQ(actions[0].line, 2);
  EXPECT_EQ(actions[1].numbers, std::vector<double>{0.5});
  EXPECT_TRUE(actions[2].flag);
  EXPECT_EQ(actions[3].scalpels.size(), 2u);
  EXPECT_DOUBLE_EQ(actions[3].open, 0.01);
  EXPECT_EQ(actions[4].points.size(), 2u);
  EXPECT_EQ(actions[5].numbers.size(), 7u);
  EXPECT_TRUE(actions[5].flag);
  EXPECT_EQ(actions[6].text, "a b.glb");
  const auto fails = [](const std::string& text, const std::string& message) {
    try {
      (void)cgamesh::session::parse_script(text, "s.txt");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InvalidInputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  fails("clip 0\nfly\n", "s.txt:2: unknown action 'fly'");
  fails("cut 0,1,0\n", "s.txt:1:");
  fails("time -1\n", "s.txt:1: time");
  fails("time nan\n", "s.txt:1:");
  fails("tear 0,1,1,0,1,0\n", "at least 2");
  fails("wait 1.5\n", "whole number");
  fails("blend cubic\n", "format, linear or log");
  fails("save \"open\n", "quote");
  fails("undo now\n", "expected 0");
  fails("tissue 1\n", "s.txt:1: tissue: the tension");
  fails("tissue on\n", "tissue TENSION");
}

TEST(Script, TissueActionsTurnItOnAndOffAndBake) {
  Session s(cesium());
  const auto actions = cgamesh::session::parse_script(
      "tissue 0.25\ntear 0.01,0.90,2,0.01,0.90,0.06 -0.03,1.0,2,-0.03,1.0,0.06\nbake\ntissue off\n", "s.txt");
  ASSERT_EQ(actions.size(), 4u);
  (void)cgamesh::session::apply(s, actions[0]);
  ASSERT_NE(s.tissue(), nullptr);
  EXPECT_DOUBLE_EQ(s.tissue()->options().pretension, 0.25);
  (void)cgamesh::session::apply(s, actions[1]);
  EXPECT_GT(s.tissue()->free_particles(), 0u);
  for (int frame = 0; frame < 30; ++frame) (void)s.step_tissue(1.0 / 30);
  const auto baked = cgamesh::session::apply(s, actions[2]);
  ASSERT_TRUE(baked.has_value());
  EXPECT_EQ(baked->kind, "bake tissue");
  (void)cgamesh::session::apply(s, actions[3]);
  EXPECT_EQ(s.tissue(), nullptr);
}

TEST(Script, JointActionsChangeOnePartOfTheEdit) {
  Session s(cesium());
  const std::string joint(s.model().skeleton.names()[3]);
  for (const auto& a : cgamesh::session::parse_script(
           "joint " + joint + ":rotate=0,0,1,30\njoint " + joint + ":translate=0.1,0,0\n", "s"))
    (void)cgamesh::session::apply(s, a);
  ASSERT_EQ(s.edits().size(), 1u);
  EXPECT_NEAR(s.edits()[0].angle, 30 * M_PI / 180, 1e-12);
  EXPECT_NEAR(s.edits()[0].translation.x(), 0.1, 1e-12);
  const auto view = cgamesh::session::parse_script("view front\n", "s");
  EXPECT_THROW((void)cgamesh::session::apply(s, view[0]), InvalidInputError);
}

}  // namespace

// The tools the viewer places from a click and a drag: a drill along the normal or the view,
// and the cut plane holding the view ray and the dragged line.
TEST(SessionTools, DrillAxisAlongTheNormalOrTheView) {
  cgamesh::session::Pick at;
  at.point = {1, 2, 3};
  at.normal = {0, 0, 1};
  const Eigen::Vector3d view = Eigen::Vector3d(0, -2, 0);
  const auto n = Session::drill_axis(at, view, false, 0.4);
  EXPECT_TRUE(n.axis.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(n.base.isApprox(Eigen::Vector3d(1, 2, 3.1)));
  EXPECT_TRUE(n.tip.isApprox(Eigen::Vector3d(1, 2, 2.6)));
  const auto v = Session::drill_axis(at, view, true, 0.4);
  EXPECT_TRUE(v.axis.isApprox(Eigen::Vector3d(0, 1, 0)));  // against the view: out of the screen
  EXPECT_TRUE(v.tip.isApprox(Eigen::Vector3d(1, 1.6, 3)));
}

TEST(SessionTools, CutNormalHoldsTheRayAndTheDrag) {
  const Eigen::Vector3d point(0, 1, 0), view(0, 0, -1);
  const auto n = Session::cut_normal(point, view, point + Eigen::Vector3d(1, 0.5, 0));
  ASSERT_TRUE(n.has_value());
  EXPECT_NEAR(n->norm(), 1, 1e-12);
  EXPECT_NEAR(n->dot(view), 0, 1e-12);
  EXPECT_NEAR(n->dot(Eigen::Vector3d(1, 0.5, 0)), 0, 1e-12);
  EXPECT_FALSE(Session::cut_normal(point, view, point + 2 * view).has_value());
  EXPECT_FALSE(Session::cut_normal(point, view, point).has_value());
}
