#include "cgamesh/session/session.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/text_values.hpp"

namespace cgamesh::session {
namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// `x` in the fewest digits that read back as the same double (0.9, not 0.90000000000000002).
std::string exact(double x) {
  std::array<char, 32> buffer{};
  const auto end = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x).ptr;
  return std::string(buffer.data(), end);
}

std::string exact(std::initializer_list<double> xs) {
  std::string out;
  for (const double x : xs) out += (out.empty() ? "" : ",") + exact(x);
  return out;
}

std::string vector_text(const Eigen::Vector3d& v) { return exact({v.x(), v.y(), v.z()}); }

/// `word` quoted for a POSIX shell when it holds more than letters, digits and ,.:=/_+-.
std::string shell_word(const std::string& word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || std::string_view(",.:=/_+-").find(static_cast<char>(c)) != std::string_view::npos;
  });
  if (plain) return word;
  std::string out = "'";
  for (const char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

int face_total(const anim::RiggedModel& model) {
  long long n = 0;
  for (const mesh::Mesh& m : model.meshes) n += m.face_count();
  return static_cast<int>(n);
}

}  // namespace

Session::Session(anim::RiggedModel model, SessionOptions options)
    : options_(std::move(options)),
      original_(std::move(model)),
      live_(original_, surgery::place(original_, anim::rest_pose(original_.skeleton))),
      source_(options_.model_file) {}

// ---- Animation ----

void Session::set_clip(int clip) {
  if (clip < -1 || clip >= static_cast<int>(model().clips.size()))
    throw InvalidInputError("clip " + std::to_string(clip) + ": the model has " + std::to_string(model().clips.size()) +
                            " clips");
  if (clip != clip_) ++pose_version_;
  clip_ = clip;
}

void Session::set_time(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0)
    throw InvalidInputError("time: must be a finite number >= 0, got " + io::number(seconds));
  if (seconds != time_) ++pose_version_;
  time_ = seconds;
}

double Session::duration() const noexcept {
  return clip_ >= 0 ? model().clips[static_cast<std::size_t>(clip_)].duration : 0.0;
}

void Session::set_blend(anim::BlendMode mode) {
  if (mode != blend_) ++pose_version_;
  blend_ = mode;
}

anim::JointEdit Session::edit_of(int joint) const noexcept {
  for (const anim::JointEdit& e : edits_)
    if (e.joint == joint) return e;
  anim::JointEdit none;
  none.joint = joint;
  return none;
}

void Session::set_edit(const anim::JointEdit& edit) {
  if (edit.joint < 0 || edit.joint >= static_cast<int>(model().skeleton.size()))
    throw InvalidInputError("joint edit: joint index " + std::to_string(edit.joint) + " is not in the skeleton");
  if (!edit.axis.allFinite() || !(edit.axis.norm() > 0))
    throw InvalidInputError("joint edit: the rotation axis must be finite and not zero");
  if (!std::isfinite(edit.angle) || !edit.translation.allFinite())
    throw InvalidInputError("joint edit: the angle and the translation must be finite");
  if (!(edit.scale > 0) || !std::isfinite(edit.scale))
    throw InvalidInputError("joint edit: the scale must be > 0 (a CGA dilator), got " + io::number(edit.scale));
  anim::JointEdit e = edit;
  e.axis.normalize();
  const auto it =
      std::find_if(edits_.begin(), edits_.end(), [&](const anim::JointEdit& x) { return x.joint == e.joint; });
  if (it != edits_.end())
    *it = e;
  else
    edits_.push_back(e);
  ++pose_version_;
}

void Session::clear_edits() {
  if (!edits_.empty()) ++pose_version_;
  edits_.clear();
}

void Session::set_morph_weight(const std::string& target, float weight) {
  anim::Pose probe = pose();
  anim::set_morph_weight(probe, model().meshes, target, weight);  // checks the name and the weight
  const auto it = std::find_if(morphs_.begin(), morphs_.end(),
                               [&](const anim::MorphSetting& m) { return m.target == target; });
  if (it != morphs_.end())
    it->weight = weight;
  else
    morphs_.push_back({target, weight});
  ++pose_version_;
}

void Session::clear_morph_weights() {
  if (!morphs_.empty()) ++pose_version_;
  morphs_.clear();
}

anim::Pose Session::pose() const { return pose_of(model()); }

void Session::add_key() {
  const auto it = std::find_if(keys_.begin(), keys_.end(), [&](const anim::Keyframe& k) { return k.time >= time_; });
  if (it != keys_.end() && it->time == time_)
    it->edits = edits_;
  else
    keys_.insert(it, anim::Keyframe{time_, edits_});
}

void Session::clear_keys() { keys_.clear(); }

void Session::generate_clip(const std::string& name) {
  if (stroking_) throw InvalidInputError("generate clip: finish the tear stroke first");
  if (name.empty()) throw InvalidInputError("generate clip: the clip needs a name");
  anim::KeyframeOptions o = options_.keyframes;
  o.name = name;
  anim::Clip clip = anim::generate_clip(model().skeleton, keys_, o);
  push_undo();
  anim::RiggedModel m = live_.model();
  m.clips.push_back(std::move(clip));
  const int index = static_cast<int>(m.clips.size()) - 1;
  edits_.clear();
  clip_ = index;
  ++pose_version_;
  replace_model(std::move(m));
  redo_.clear();
}

// ---- Surgery ----

double Session::place_now() {
  // A stroke is torn against the placement it began in.
  if (placed_version_ == pose_version_ || stroking_) return 0;
  const auto start = Clock::now();
  const anim::Pose p = pose();
  anim::RiggedModel m = std::move(live_).release();
  surgery::Placement placement = surgery::place(m, p);
  live_ = surgery::LiveModel(std::move(m), std::move(placement));
  placed_version_ = pose_version_;
  return milliseconds_since(start);
}

void Session::replace_model(anim::RiggedModel model) {
  surgery::Placement placement = surgery::place(model, pose_of(model));
  live_ = surgery::LiveModel(std::move(model), std::move(placement));
  placed_version_ = pose_version_;
  restart_tissue();
}

anim::Pose Session::pose_of(const anim::RiggedModel& m) const {
  anim::Pose p = clip_ >= 0 && clip_ < static_cast<int>(m.clips.size())
                     ? anim::sample(m.skeleton, m.clips[static_cast<std::size_t>(clip_)], time_, blend_)
                     : anim::rest_pose(m.skeleton);
  anim::apply_edits(p, edits_);
  for (const anim::MorphSetting& s : morphs_) {
    const bool has = std::any_of(m.meshes.begin(), m.meshes.end(), [&](const mesh::Mesh& me) {
      return std::any_of(me.morph_targets.begin(), me.morph_targets.end(),
                         [&](const mesh::MorphTarget& t) { return t.name == s.target; });
    });
    if (has) anim::set_morph_weight(p, m.meshes, s.target, s.weight);
  }
  return p;
}

void Session::push_undo() { undo_.push_back({live_, placed_version_, source_, tissue_}); }

std::string Session::next_output() const { return "step" + std::to_string(steps_ + 1) + ".glb"; }

void Session::trim_undo() {
  while (undo_.size() > std::max<std::size_t>(options_.max_undo, 1)) undo_.erase(undo_.begin());
}

template <class Operation>
OperationReport Session::operate(Operation&& operation) {
  if (stroking_) throw InvalidInputError("finish the tear stroke first");
  OperationReport r;
  r.placement_milliseconds = place_now();
  push_undo();
  return finish(std::move(r), std::forward<Operation>(operation));
}

template <class Operation>
OperationReport Session::finish(OperationReport r, Operation&& operation) {
  try {
    const auto start = Clock::now();
    operation(r);
    r.milliseconds = milliseconds_since(start);
  } catch (...) {
    // The operations leave a LiveModel unchanged when they throw; the snapshot is not needed.
    undo_.pop_back();
    throw;
  }
  redo_.clear();
  trim_undo();
  r.faces = face_total(model());
  source_ = next_output();  // the next operation acts on this one's result
  ++steps_;
  return r;
}

std::string Session::pose_arguments() const {
  std::string out;
  if (clip_ >= 0)
    out += " --anim " + std::to_string(clip_) + " --time " + exact(time_) + " --blend " + io::blend_name(blend_);
  const auto& names = model().skeleton.names();
  for (const anim::JointEdit& e : edits_) {
    const std::string joint = names[static_cast<std::size_t>(e.joint)];
    // apply_edits composes T R D: one --set per part, in that order, composes the same.
    if (!e.translation.isZero(0)) out += " --set " + shell_word(joint + ":translate=" + vector_text(e.translation));
    if (e.angle != 0)
      out += " --set " +
             shell_word(joint + ":rotate=" + vector_text(e.axis) + "," + exact(e.angle * 180 / std::numbers::pi));
    if (e.scale != 1) out += " --set " + shell_word(joint + ":scale=" + exact(e.scale));
  }
  for (const anim::MorphSetting& m : morphs_) out += " --morph " + shell_word(m.target + "=" + exact(m.weight));
  return out;
}

namespace {

std::string rest_argument(surgery::RestPosition rest) {
  return rest == surgery::RestPosition::parametric ? " --rest parametric" : "";
}

}  // namespace

OperationReport Session::cut(const Eigen::Vector3d& normal, double d, const surgery::CutOptions& options) {
  cga::Vector<double> plane;
  try {
    plane = surgery::cut_plane(normal, d);
  } catch (const Error&) {
    rethrow_with_context("cut: ");
  }
  return operate([&](OperationReport& r) {
    r.kind = "cut";
    r.command = "cut " + shell_word(source_) + pose_arguments() + " --plane " +
                exact({normal.x(), normal.y(), normal.z(), d}) + (options.cap ? " --cap" : "") +
                (options.own_side_influences ? " --own-side-influences" : "") + rest_argument(options.rest) + " -o " +
                next_output();
    if (!options.cap) {
      const surgery::LiveCut c = surgery::cut(live_, plane, options);
      r.warnings = c.warnings;
      follow_tissue(c.changes);
      return;
    }
    surgery::ModelCut c = surgery::cut(live_.model(), live_.placement(), plane, options);
    r.warnings = c.warnings;
    replace_model(surgery::join_pieces(std::move(c.pieces)));
  });
}

std::string Session::tear_command(std::span<const surgery::Scalpel> scalpel, const surgery::TearOptions& options,
                                  const std::string& pose) const {
  std::string out = "tear " + shell_word(source_) + pose;
  for (const surgery::Scalpel& s : scalpel) out += " --scalpel " + vector_text(s.handle) + "," + vector_text(s.tip);
  if (options.open > 0) out += " --open " + exact(options.open);
  if (options.own_side_influences) out += " --own-side-influences";
  return out + rest_argument(options.rest) + " -o " + next_output();
}

OperationReport Session::tear(std::span<const surgery::Scalpel> scalpel, const surgery::TearOptions& options) {
  return operate([&](OperationReport& r) {
    r.kind = "tear";
    r.command = tear_command(scalpel, options, pose_arguments());
    const surgery::LiveTear t = surgery::tear(live_, scalpel, options);
    r.warnings = t.warnings;
    follow_tissue(std::span(&t.change, 1));
  });
}

OperationReport Session::drill(const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                               const surgery::DrillOptions& options) {
  return operate([&](OperationReport& r) {
    r.kind = "drill";
    const surgery::DrillOptions defaults;
    r.command = "drill " + shell_word(source_) + pose_arguments() + " --tip " + vector_text(tip) + " --base " +
                vector_text(base) + " --radius " + exact(radius) + (options.wall ? " --wall" : "") +
                (options.min_rim_points != defaults.min_rim_points
                     ? " --min-rim-points " + std::to_string(options.min_rim_points)
                     : "") +
                (options.max_refinements != defaults.max_refinements
                     ? " --max-refinements " + std::to_string(options.max_refinements)
                     : "") +
                (options.max_region_faces != defaults.max_region_faces
                     ? " --max-region-faces " + std::to_string(options.max_region_faces)
                     : "") +
                rest_argument(options.rest) + " -o " + next_output();
    const surgery::LiveDrill d = surgery::drill(live_, tip, base, radius, options);
    r.warnings = d.warnings;
    follow_tissue(d.changes);
  });
}

OperationReport Session::deform(const deform::BoundDeformer& deformer, std::span<const cga::Versor<double>> keys,
                                const std::string& spec) {
  const int i = deformer.mesh_index();
  if (i < 0 || i >= static_cast<int>(model().meshes.size()) ||
      model().meshes[static_cast<std::size_t>(i)].vertex_count() != deformer.vertex_count())
    throw InvalidInputError("deform: the model changed since the spec was bound (mesh " + std::to_string(i) +
                            " no longer has its " + std::to_string(deformer.vertex_count()) +
                            " vertices); bind it again");
  return operate([&](OperationReport& r) {
    r.kind = "deform";
    r.command = "deform " + shell_word(source_) + " --spec " + shell_word(spec) + " -o " + next_output();
    replace_model(deformer.deformed_model(model(), deformer.apply(keys)));
  });
}

void Session::begin_stroke() {
  if (stroking_) throw InvalidInputError("a tear stroke is already under way");
  place_now();
  push_undo();
  stroking_ = true;
  stroke_.clear();
  stroke_pose_ = pose_arguments();
}

std::optional<OperationReport> Session::stroke_step(const surgery::Scalpel& blade, std::string* error) {
  if (!stroking_) throw InvalidInputError("stroke step: no tear stroke was begun");
  stroke_.push_back(blade);
  if (stroke_.size() < 2) return std::nullopt;
  const std::array<surgery::Scalpel, 2> step{stroke_[stroke_.size() - 2], stroke_.back()};
  OperationReport r;
  r.kind = "tear step";
  try {
    const auto start = Clock::now();
    const surgery::LiveTear t = surgery::tear(live_, step);
    r.warnings = t.warnings;
    follow_tissue(std::span(&t.change, 1));
    r.milliseconds = milliseconds_since(start);
  } catch (const Error& e) {
    stroke_.pop_back();
    if (error != nullptr) *error = e.what();
    return std::nullopt;
  }
  r.command = tear_command(step, {}, stroke_pose_);
  r.faces = face_total(model());
  return r;
}

std::optional<OperationReport> Session::end_stroke(const surgery::TearOptions& options) {
  if (!stroking_) return std::nullopt;
  stroking_ = false;
  if (stroke_.size() < 2) {
    end_stroke_discarding();
    return std::nullopt;
  }
  const Snapshot& before = undo_.back();
  // The steps torn while dragging are replaced by one tear over the whole stroke, as the
  // command line makes it: one path, opened over its whole length.
  live_ = before.live;
  placed_version_ = before.placed_version;
  restore_tissue(tissue_ ? std::optional(tissue_->options()) : std::nullopt, before.tissue);
  OperationReport r;
  r.kind = "tear";
  r.command = tear_command(stroke_, options, stroke_pose_);
  return finish(std::move(r), [&](OperationReport& x) {
    const surgery::LiveTear t = surgery::tear(live_, stroke_, options);
    x.warnings = t.warnings;
    follow_tissue(std::span(&t.change, 1));
  });
}

bool Session::undo() { return !stroking_ && step_history(undo_, redo_); }

bool Session::redo() { return !stroking_ && step_history(redo_, undo_); }

bool Session::step_history(std::vector<Snapshot>& from, std::vector<Snapshot>& to) {
  if (from.empty()) return false;
  to.push_back({std::move(live_), placed_version_, source_, std::move(tissue_)});
  live_ = std::move(from.back().live);
  placed_version_ = from.back().placed_version;
  source_ = from.back().source;
  restore_tissue(to.back().tissue ? std::optional(to.back().tissue->options()) : std::nullopt,
                 std::move(from.back().tissue));
  from.pop_back();
  after_model_change();
  return true;
}

void Session::reset() {
  if (stroking_) end_stroke_discarding();
  undo_.clear();
  redo_.clear();
  source_ = options_.model_file;
  after_model_change(original_);
  replace_model(original_);
}

void Session::end_stroke_discarding() {
  stroking_ = false;
  live_ = std::move(undo_.back().live);
  placed_version_ = undo_.back().placed_version;
  restore_tissue(tissue_ ? std::optional(tissue_->options()) : std::nullopt, std::move(undo_.back().tissue));
  undo_.pop_back();
}

void Session::after_model_change() { after_model_change(model()); }

void Session::after_model_change(const anim::RiggedModel& m) {
  // A generated clip undone (or reset away) cannot stay selected.
  if (clip_ >= static_cast<int>(m.clips.size())) {
    clip_ = -1;
    ++pose_version_;
  }
}

// ---- Living tissue ----

void Session::set_tissue(const std::optional<soft::TissueOptions>& options) {
  if (!options) {
    tissue_.reset();
    return;
  }
  if (tissue_) {
    tissue_->set_options(live_, *options);
    return;
  }
  place_now();
  tissue_.emplace(live_, *options);
}

void Session::follow_tissue(std::span<const surgery::MeshChange> changes) {
  if (tissue_) tissue_->follow(live_, changes);
}

void Session::restore_tissue(const std::optional<soft::TissueOptions>& now, std::optional<soft::Tissue> saved) {
  if (!now) {
    tissue_.reset();
    return;
  }
  tissue_ = std::move(saved);
  if (!tissue_)
    tissue_.emplace(live_, *now);
  else if (!(tissue_->options() == *now))
    tissue_->set_options(live_, *now);
}

void Session::restart_tissue() {
  if (tissue_) tissue_.emplace(live_, soft::TissueOptions(tissue_->options()));
}

double Session::step_tissue(double dt) {
  if (!tissue_) return 0;
  const auto start = Clock::now();
  tissue_->step(live_, pose(), dt);
  return milliseconds_since(start);
}

std::vector<mesh::RowMatrixXf<3>> Session::tissue_positions() const {
  if (tissue_) return tissue_->positions(live_, pose());
  return surgery::place(model(), pose()).positions;
}

OperationReport Session::bake_tissue() {
  if (!tissue_) throw InvalidInputError("bake: the tissue is off");
  if (stroking_) throw InvalidInputError("bake: finish the tear stroke first");
  const auto start = Clock::now();
  OperationReport r;
  r.kind = "bake tissue";
  r.placement_milliseconds = place_now();
  anim::RiggedModel baked = tissue_->bake(live_, pose());
  push_undo();
  replace_model(std::move(baked));
  redo_.clear();
  trim_undo();
  r.milliseconds = milliseconds_since(start);
  r.faces = face_total(model());
  // The command line has no bake of its own: --soft settles and bakes one operation.
  r.warnings.push_back("the baked tissue has no replay command: the commands that follow read the file before it "
                       "(the command line bakes with --soft on the operation)");
  return r;
}

// ---- Picking ----

std::optional<Pick> Session::pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  if (!origin.allFinite() || !direction.allFinite() || !(direction.norm() > 0))
    throw InvalidInputError("pick: the ray must be finite, with a non-zero direction");
  place_now();
  const Eigen::Vector3d dir = direction.normalized();
  const auto [lo, hi] = placed_bounds();
  if (!(hi.array() >= lo.array()).all()) return std::nullopt;
  const double reach = 2 * (hi - lo).norm() + (origin - (lo + hi) / 2).norm();
  const Eigen::Vector3d far = origin + dir * reach;
  std::optional<Pick> best;
  double best_t = INFINITY;
  for (std::size_t i = 0; i < live_.index().meshes.size(); ++i) {
    const std::vector<mesh::SegmentHit> hits = live_.index().meshes[i].bvh.segment_hits(origin, far);
    if (hits.empty() || hits.front().t >= best_t) continue;
    const mesh::SegmentHit& h = hits.front();
    best_t = h.t;
    const mesh::Mesh& m = model().meshes[i];
    const mesh::RowMatrixXf<3>& placed = live_.placement().positions[i];
    Pick p;
    p.mesh = static_cast<int>(i);
    p.face = h.face;
    p.point = origin + (far - origin) * h.t;
    std::array<Eigen::Vector3d, 3> c;
    for (int k = 0; k < 3; ++k)
      c[static_cast<std::size_t>(k)] = placed.row(m.faces(h.face, k)).transpose().cast<double>();
    Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]);
    n = n.norm() > 0 ? n.normalized() : Eigen::Vector3d(-dir);
    p.normal = n.dot(dir) > 0 ? Eigen::Vector3d(-n) : n;
    int corner = 0;
    h.barycentric.maxCoeff(&corner);
    p.vertex = m.faces(h.face, corner);
    if (!m.skin.empty() && m.skin.weights(p.vertex, 0) > 0) p.joint = m.skin.palette[m.skin.joints(p.vertex, 0)];
    best = p;
  }
  return best;
}

surgery::Scalpel Session::blade(const Pick& at, const Eigen::Vector3d& view_direction, double depth) {
  const Eigen::Vector3d d = view_direction.normalized() * depth;
  return {at.point - d, at.point + d};
}

Session::DrillAxis Session::drill_axis(const Pick& at, const Eigen::Vector3d& view_direction, bool along_view,
                                       double depth) {
  const Eigen::Vector3d axis = along_view ? Eigen::Vector3d(-view_direction.normalized()) : at.normal;
  return {axis, at.point + axis * (0.25 * depth), at.point - axis * depth};
}

std::optional<Eigen::Vector3d> Session::cut_normal(const Eigen::Vector3d& point, const Eigen::Vector3d& view_direction,
                                                   const Eigen::Vector3d& dragged) {
  const Eigen::Vector3d along = dragged - point;
  const Eigen::Vector3d n = along.cross(view_direction);
  if (n.norm() > 1e-12 * std::max(along.norm(), 1.0)) return n.normalized();
  return std::nullopt;
}

double Session::size() const {
  const auto [lo, hi] = placed_bounds();
  return (hi.array() >= lo.array()).all() ? (hi - lo).norm() : 0.0;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> Session::placed_bounds() const {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const mesh::RowMatrixXf<3>& p : live_.placement().positions)
    if (p.rows() > 0) {
      lo = lo.cwiseMin(p.colwise().minCoeff().transpose());
      hi = hi.cwiseMax(p.colwise().maxCoeff().transpose());
    }
  return {lo.cast<double>(), hi.cast<double>()};
}

// ---- Saving ----

void Session::save(const std::filesystem::path& path, anim::SkinningMode mode) const {
  (void)io::write_model(model(), path, [&]() -> mesh::WorldSurface { return io::posed_frame(model(), pose(), mode); });
}

}  // namespace cgamesh::session
