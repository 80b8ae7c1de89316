#pragma once
// An interactive editing session on one rigged model: the animation state a viewer shows (clip,
// time, blend mode, joint edits, keyframes generated on the fly), surgery in place on the model
// as posed (surgery::LiveModel) with undo and redo, picking on the placed surface, and saving.
// No window and no OpenGL: the viewer and its scripts drive it, and tests run it headless.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/keyframes.hpp"
#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/soft/tissue.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/tear.hpp"

namespace cgamesh::session {

/// What one surgery operation did, for a panel, a log or a test.
struct OperationReport {
  std::string kind;                   ///< "cut", "tear", "tear step" or "drill"
  double milliseconds = 0;            ///< the operation alone
  double placement_milliseconds = 0;  ///< placing and indexing the model first (0 when the pose had not changed)
  /// The `cgamesh` command that does the same to a file (the tool's parameters and the pose,
  /// numbers in the fewest digits that read back exactly). The commands chain: the first reads
  /// SessionOptions::model_file, each writes stepN.glb (N = 1, 2, ...
  /// over the session) and the next reads what the one before wrote (after an undo, what the
  /// model shown came from). A cut writes both pieces to one file, as the session holds them.
  std::string command;
  int faces = 0;  ///< faces of the model after the operation
  std::vector<std::string> warnings;
};

/// A point of the placed surface hit by a ray.
struct Pick {
  int mesh = -1;
  int face = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< world space, as placed in the current pose
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit face normal, facing the ray's origin
  int vertex = -1;                                    ///< the corner of the face nearest the point
  int joint = -1;  ///< the joint with the largest skin weight at `vertex`; −1 for a static mesh
};

struct SessionOptions {
  std::size_t max_undo = 16;         ///< snapshots kept for undo (each is a copy of the model and its index)
  anim::KeyframeOptions keyframes;   ///< how generate_clip() bakes the keys
  std::string model_file = "MODEL";  ///< the model's file, as the first replay command reads it
};

class Session {
 public:
  /// Starts on the bind pose (no clip) of `model`.
  /// @throws InvalidInputError when the model cannot be placed (NaN positions).
  explicit Session(anim::RiggedModel model, SessionOptions options = {});

  /// The model as edited so far (surgery, generated clips).
  [[nodiscard]] const anim::RiggedModel& model() const noexcept { return live_.model(); }
  /// The model's SurfaceIndex (its welds tell the pieces that surgery separated apart).
  [[nodiscard]] const surgery::SurfaceIndex& index() const noexcept { return live_.index(); }

  // ---- Animation ----
  [[nodiscard]] int clip() const noexcept { return clip_; }  ///< −1: the bind pose
  /// Shows clip `clip` (−1: the bind pose), keeping the time.
  /// @throws InvalidInputError for a clip the model does not have.
  void set_clip(int clip);
  [[nodiscard]] double time() const noexcept { return time_; }
  /// @throws InvalidInputError for a negative or non-finite time.
  void set_time(double seconds);
  /// Length of the current clip in seconds (0 for the bind pose).
  [[nodiscard]] double duration() const noexcept;
  [[nodiscard]] anim::BlendMode blend() const noexcept { return blend_; }
  void set_blend(anim::BlendMode mode);

  /// The edit of each edited joint, applied after the clip (one per joint).
  [[nodiscard]] const std::vector<anim::JointEdit>& edits() const noexcept { return edits_; }
  /// The edit of `joint` (the identity when it has none).
  [[nodiscard]] anim::JointEdit edit_of(int joint) const noexcept;
  /// Replaces the edit of edit.joint.
  /// @throws InvalidInputError for a joint out of range, a zero or non-finite axis, a
  ///         non-finite angle or translation, or a scale that is not positive.
  void set_edit(const anim::JointEdit& edit);
  void clear_edits();

  /// Morph weights set by target name over the clip's or the file's, in the order first set.
  [[nodiscard]] const std::vector<anim::MorphSetting>& morph_settings() const noexcept { return morphs_; }
  /// Sets every morph target named `target` to `weight` (anim::set_morph_weight): a slider.
  /// @throws InvalidInputError when no mesh has a target so named, or `weight` is not finite.
  void set_morph_weight(const std::string& target, float weight);
  /// Back to the clip's or the file's morph weights.
  void clear_morph_weights();

  /// The pose shown: the clip sampled at the time (or the bind pose), then the edits and the
  /// morph settings.
  [[nodiscard]] anim::Pose pose() const;

  /// Keys the current edits at the current time (paper section 4: a keyframe is the bind pose
  /// with edits), replacing a key at the same time.
  void add_key();
  [[nodiscard]] const std::vector<anim::Keyframe>& keys() const noexcept { return keys_; }
  void clear_keys();
  /// Bakes the keys into a new clip of the model (anim::generate_clip with options.keyframes and
  /// `name`), selects it and clears the edits, so that playing shows the generated animation.
  /// @throws InvalidInputError for an empty name, or as anim::generate_clip (e.g. fewer than
  ///         two keys).
  void generate_clip(const std::string& name);

  // ---- Surgery on the model as posed now (placed with `cga` skinning, eq. 17) ----
  /// Cuts with the plane n·x = d. Without options.cap the cut is made in place (surgery::cut
  /// on the LiveModel: the pieces stay in their meshes); with it, both capped pieces
  /// (surgery::cut) become the meshes of the model, piece A's first.
  /// @throws as surgery::cut; the session is then unchanged.
  OperationReport cut(const Eigen::Vector3d& normal, double d, const surgery::CutOptions& options = {});
  /// Tears along the path of `scalpel` (≥ 2 blade positions, Algorithm 2), in place.
  /// @throws as surgery::tear; the session is then unchanged.
  OperationReport tear(std::span<const surgery::Scalpel> scalpel, const surgery::TearOptions& options = {});
  /// Drills with the cylinder of `radius` from `base` to `tip`, in place.
  /// @throws as surgery::drill; the session is then unchanged.
  OperationReport drill(const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                        const surgery::DrillOptions& options = {});

  /// Deforms the model's rest shape by `deformer` under `keys` (deform/bound_deformer.hpp: the mesh it
  /// was bound to gets BoundDeformer::deformed_model's rest shape, skin, skeleton and clips
  /// kept), as one undo step. `spec` names the spec in the report's command.
  /// @throws InvalidInputError when the deformer was bound to a mesh of another vertex count
  ///         (the model changed since), or as BoundDeformer::apply.
  OperationReport deform(const deform::BoundDeformer& deformer, std::span<const cga::Versor<double>> keys,
                         const std::string& spec);

  /// A tear made by dragging: begin_stroke(), then stroke_step() per blade position, each
  /// step past the first torn in place at once (so the tear grows while dragging), then
  /// end_stroke(), which makes the whole stroke one tear over all its steps with `options`
  /// (the opening spread over the whole tear) and one undo step.
  void begin_stroke();
  /// Adds a blade position; from the second on, tears the step from the previous one in place
  /// (without opening). A step the blade cannot make (it misses the surface, or the path
  /// cannot be followed) is dropped: the report is empty then and `error` says why.
  std::optional<OperationReport> stroke_step(const surgery::Scalpel& blade, std::string* error = nullptr);
  [[nodiscard]] bool stroking() const noexcept { return stroking_; }
  [[nodiscard]] std::span<const surgery::Scalpel> stroke() const noexcept { return stroke_; }
  /// Ends the stroke; with fewer than two positions kept nothing changes (no report).
  /// @throws as tear(); the model is then as before the stroke.
  std::optional<OperationReport> end_stroke(const surgery::TearOptions& options = {});

  // ---- Living tissue (soft/tissue.hpp) on the model as edited in place ----
  /// Turns the tissue on with `options` (or changes them, keeping its state), or off (nullopt).
  /// Every in-place cut, tear, drill and stroke step is followed; an operation that replaces
  /// the model (a capped cut, a deformation, a generated clip, undo to before the tissue's
  /// wounds) starts it afresh on the new model. Not an undo step.
  /// @throws InvalidInputError as TissueOptions::validate() (the tissue is then as before).
  void set_tissue(const std::optional<soft::TissueOptions>& options);
  /// The tissue, or null when it is off.
  [[nodiscard]] const soft::Tissue* tissue() const noexcept { return tissue_ ? &*tissue_ : nullptr; }
  /// Advances the tissue by `dt` seconds towards the current pose (nothing when it is off);
  /// returns the milliseconds it took.
  /// @throws as soft::Tissue::step (SolverError: the tissue is then as before).
  double step_tissue(double dt);
  /// Per mesh, #V×3 world positions of the surface as the tissue has it now (simulated near the
  /// wounds, skinned elsewhere), or the skinned positions when it is off.
  [[nodiscard]] std::vector<mesh::RowMatrixXf<3>> tissue_positions() const;
  /// Writes the tissue's surface into the model (soft::Tissue::bake in the current pose) as one
  /// undo step: the wound keeps its simulated shape as the model animates, and the tissue
  /// starts afresh on it.
  /// @throws InvalidInputError when the tissue is off or during a stroke.
  OperationReport bake_tissue();

  [[nodiscard]] bool can_undo() const noexcept { return !undo_.empty() && !stroking_; }
  [[nodiscard]] bool can_redo() const noexcept { return !redo_.empty() && !stroking_; }
  /// Goes back to before the last operation; false when there is none.
  bool undo();
  /// Makes the last undone operation again; false when there is none.
  bool redo();
  /// The model as loaded: every operation and generated clip gone, undo and redo cleared.
  void reset();

  /// The first point of the placed surface (current pose) on the ray, if any.
  /// @throws InvalidInputError for a non-finite origin or a zero direction.
  [[nodiscard]] std::optional<Pick> pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

  /// The blade of a dragged tear at a picked point: from `depth` before the point along the
  /// view direction (the handle, above the surface) to `depth` behind it (the tip, below).
  [[nodiscard]] static surgery::Scalpel blade(const Pick& at, const Eigen::Vector3d& view_direction, double depth);

  /// A drill placed at a picked point: its axis along the surface's normal there, or against
  /// `view_direction` when `along_view`; the base `depth`/4 above the point, the tip `depth`
  /// below it.
  struct DrillAxis {
    Eigen::Vector3d axis, base, tip;
  };
  [[nodiscard]] static DrillAxis drill_axis(const Pick& at, const Eigen::Vector3d& view_direction, bool along_view,
                                            double depth);

  /// The normal of the cut plane through `point` that holds the view ray `view_direction` and
  /// the line dragged from `point` to `dragged` (both in world space), or nothing when the drag
  /// runs along the ray.
  [[nodiscard]] static std::optional<Eigen::Vector3d> cut_normal(const Eigen::Vector3d& point,
                                                                 const Eigen::Vector3d& view_direction,
                                                                 const Eigen::Vector3d& dragged);

  /// Length of the diagonal of the bounding box of the model as last placed (the scale of
  /// tools; not placed again for a new pose, which would cost a re-index every frame of play).
  [[nodiscard]] double size() const;

  /// Writes the model: .glb/.gltf with skin, skeleton and clips; .obj/.ply as posed now
  /// (positions and normals skinned with `mode`, io::posed_frame()). All or nothing.
  /// @throws InvalidInputError for another extension; WriteError when it cannot be written.
  void save(const std::filesystem::path& path, anim::SkinningMode mode = anim::SkinningMode::cga) const;

 private:
  struct Snapshot {
    surgery::LiveModel live;
    long placed_version;
    std::string source;  ///< the file its model is, in the replay commands
    std::optional<soft::Tissue> tissue;
  };
  /// The tissue follows an in-place operation's changes.
  void follow_tissue(std::span<const surgery::MeshChange> changes);
  /// The tissue starts afresh on the model (after the model was replaced).
  void restart_tissue();
  /// After the model went back to a snapshot: off if the tissue is off `now`, else the
  /// snapshot's tissue (`saved`; afresh when it had none) with the options of `now`.
  void restore_tissue(const std::optional<soft::TissueOptions>& now, std::optional<soft::Tissue> saved);
  /// Places and indexes the model in the current pose unless it already is; returns the ms spent.
  double place_now();
  /// Runs `operation` on the placed model as one undo step: a snapshot first, dropped again
  /// if the operation throws (the model is then as before).
  template <class Operation>
  OperationReport operate(Operation&& operation);
  /// Runs `operation` after its snapshot was pushed: times it, drops the snapshot if it throws,
  /// clears redo and counts the faces.
  template <class Operation>
  OperationReport finish(OperationReport r, Operation&& operation);
  void push_undo();
  /// Makes the last snapshot of `from` the model, the model the last of `to` (undo, redo).
  bool step_history(std::vector<Snapshot>& from, std::vector<Snapshot>& to);
  /// Drops the oldest snapshots beyond options.max_undo.
  void trim_undo();
  /// Makes `model` the session's, placed in the current pose.
  void replace_model(anim::RiggedModel model);
  /// The current clip, time, blend, edits and morph settings applied to `model` (a clip it lacks:
  /// the bind pose; a morph target it lacks: no weight).
  [[nodiscard]] anim::Pose pose_of(const anim::RiggedModel& model) const;
  /// A clip that `model` no longer has (a generated clip undone or reset away) is unselected.
  void after_model_change(const anim::RiggedModel& model);
  void after_model_change();
  /// Back to the snapshot taken when the stroke began.
  void end_stroke_discarding();
  /// The file the next operation's command writes: step{steps_ + 1}.glb.
  [[nodiscard]] std::string next_output() const;
  /// " --anim I --time T --blend B --set ..." for the current pose.
  [[nodiscard]] std::string pose_arguments() const;
  [[nodiscard]] std::string tear_command(std::span<const surgery::Scalpel> scalpel, const surgery::TearOptions& options,
                                         const std::string& pose) const;
  /// Corners of the box around the placed model (lo > hi when it has no vertex).
  [[nodiscard]] std::pair<Eigen::Vector3d, Eigen::Vector3d> placed_bounds() const;

  SessionOptions options_;
  anim::RiggedModel original_;
  surgery::LiveModel live_;
  std::optional<soft::Tissue> tissue_;
  long pose_version_ = 0;    ///< bumped by every change of the pose
  long placed_version_ = 0;  ///< the pose version live_ is placed in (−1: none)
  int clip_ = -1;
  double time_ = 0;
  anim::BlendMode blend_ = anim::BlendMode::format;
  std::vector<anim::JointEdit> edits_;
  std::vector<anim::MorphSetting> morphs_;
  std::vector<anim::Keyframe> keys_;
  std::vector<Snapshot> undo_, redo_;
  bool stroking_ = false;
  std::vector<surgery::Scalpel> stroke_;
  std::string stroke_pose_;  ///< pose_arguments() when the stroke began
  std::string source_;       ///< the file the current model is, in the replay commands
  int steps_ = 0;            ///< operations finished: the last command wrote step{steps_}.glb
};

}  // namespace cgamesh::session
