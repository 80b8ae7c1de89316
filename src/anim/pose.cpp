#include "cgamesh/anim/pose.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cgamesh/cga/convert.hpp"
#include "cgamesh/cga/interpolation.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

#include "polar.hpp"

namespace cgamesh::anim {
namespace {

using cga::Vec3;

/// Key interval of `time`: keys k and k + 1 with parameter alpha in [0, 1].
struct Interval {
  std::size_t k0, k1;
  double alpha, dt;
};

Interval locate(const std::vector<double>& times, double time) {
  if (time <= times.front()) return {0, 0, 0, 0};
  if (time >= times.back()) return {times.size() - 1, times.size() - 1, 0, 0};
  const std::size_t k1 = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), time) - times.begin());
  const std::size_t k0 = k1 - 1;
  const double dt = times[k1] - times[k0];
  return {k0, k1, dt > 0 ? (time - times[k0]) / dt : 0, dt};
}

/// Component i of key k's block (cubic splines: 0 in-tangent, 1 value, 2 out-tangent).
double key_component(const Channel& c, std::size_t k, int block, int i) {
  const auto n = static_cast<std::size_t>(c.components());
  return c.interpolation == Interpolation::cubic_spline ? c.values[(3 * k + static_cast<std::size_t>(block)) * n + i]
                                                        : c.values[k * n + static_cast<std::size_t>(i)];
}

/// Value of key k (components beyond the channel's are 0).
Eigen::Vector4d key(const Channel& c, std::size_t k) {
  Eigen::Vector4d v = Eigen::Vector4d::Zero();
  for (int i = 0; i < c.components(); ++i) v[i] = key_component(c, k, 1, i);
  return v;
}

Eigen::Quaterniond quat(const Eigen::Vector4d& v) { return Eigen::Quaterniond(v[3], v[0], v[1], v[2]); }

/// Component i of glTF's cubic Hermite spline between keys k0 and k1.
double hermite(const Channel& c, const Interval& iv, int i) {
  const double t = iv.alpha, t2 = t * t, t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * key_component(c, iv.k0, 1, i) +
         (t3 - 2 * t2 + t) * iv.dt * key_component(c, iv.k0, 2, i) + (-2 * t3 + 3 * t2) * key_component(c, iv.k1, 1, i) +
         (t3 - t2) * iv.dt * key_component(c, iv.k1, 0, i);
}

/// The morph weights of a weights channel at the interval, as the file says to interpolate them
/// (weights are plain numbers: every blend mode lerps them, as glTF does).
void evaluate_weights(const Channel& c, const Interval& iv, std::vector<float>& out) {
  const int n = c.components();
  out.resize(static_cast<std::size_t>(n));
  const bool hold = c.interpolation == Interpolation::step || iv.k0 == iv.k1;
  const double t = hold ? 0.0 : iv.alpha;
  for (int i = 0; i < n; ++i)
    out[static_cast<std::size_t>(i)] = static_cast<float>(
        c.interpolation == Interpolation::cubic_spline && !hold
            ? hermite(c, iv, i)
            : (1 - t) * key_component(c, iv.k0, 1, i) + t * key_component(c, iv.k1, 1, i));
}

/// Translation, rotation or scale of one channel at the interval, blended in `mode`.
void evaluate(const Channel& c, const Interval& iv, BlendMode mode, Transform& out) {
  if (c.interpolation == Interpolation::cubic_spline && iv.k0 != iv.k1) {
    // Tangents have no versor meaning: splines are always evaluated as the file says.
    Eigen::Vector4d v = Eigen::Vector4d::Zero();
    for (int i = 0; i < c.components(); ++i) v[i] = hermite(c, iv, i);
    if (c.path == ChannelPath::translation)
      out.translation = v.head<3>();
    else if (c.path == ChannelPath::scale)
      out.scale = v.head<3>();
    else
      out.rotation = quat(v).normalized();
    return;
  }
  const bool hold = c.interpolation == Interpolation::step || iv.k0 == iv.k1;
  const double a = hold ? 0.0 : iv.alpha;
  const Eigen::Vector4d v0 = key(c, iv.k0), v1 = key(c, iv.k1);
  switch (c.path) {
    case ChannelPath::translation:
      // Translators blend linearly in t under every mode: lerp and log blend agree.
      out.translation = (1 - a) * v0.head<3>() + a * v1.head<3>();
      return;
    case ChannelPath::rotation: {
      if (mode == BlendMode::format) {
        out.rotation = quat(v0).normalized().slerp(a, quat(v1).normalized());
        return;
      }
      const cga::Rotor<double> r0 = cga::rotor(quat(v0));
      cga::Rotor<double> r1 = cga::rotor(quat(v1));
      if (cga::scalar_product(r0, cga::reverse(r1)) < 0) r1 = -r1;  // same hemisphere: the short way
      const cga::Rotor<double> r =
          mode == BlendMode::linear ? cga::lerp_normalized(r0, r1, a) : cga::log_blend(r0, r1, a);
      out.rotation = cga::to_quaternion(r);
      return;
    }
    case ChannelPath::weights:
      return;  // evaluate_weights()
    case ChannelPath::scale: {
      if (mode == BlendMode::format) {
        out.scale = (1 - a) * v0.head<3>() + a * v1.head<3>();
        return;
      }
      const Transform s0{.scale = v0.head<3>()}, s1{.scale = v1.head<3>()};
      const cga::Dilator<double> d0 = cga::dilator(s0.uniform_scale()), d1 = cga::dilator(s1.uniform_scale());
      double s = 1;
      if (mode == BlendMode::linear) {
        const cga::Dilator<double> d = cga::lerp_normalized(d0, d1, a);
        s = 1.0 / ((d[0] + d[1]) * (d[0] + d[1]));  // D(s) = ((1 + s) + (1 - s) E) / (2 sqrt s)
      } else {
        s = cga::decompose(cga::log_blend(cga::Versor<double>(d0), cga::Versor<double>(d1), a)).scale;
      }
      out.scale = Eigen::Vector3d::Constant(s);
      return;
    }
  }
}

/// The versor T R D of affine matrix m = [L t]: R the rotation of L's polar decomposition, D its
/// volume-keeping scale |det L|^(1/3). m itself when m is a similarity.
cga::Versor<double> nearest_similarity(const Eigen::Matrix4d& m) {
  Eigen::Matrix3d r, s;
  detail::rotation_scaling(m.topLeftCorner<3, 3>(), r, s);
  return cga::similarity(Vec3<double>(m.topRightCorner<3, 1>()), cga::rotor(Eigen::Quaterniond(r)),
                         std::cbrt(std::abs(m.topLeftCorner<3, 3>().determinant())));
}

}  // namespace

Pose rest_pose(const Skeleton& skeleton) {
  Pose p;
  p.local.assign(skeleton.rest().begin(), skeleton.rest().end());
  p.local_versors.assign(skeleton.rest_versors().begin(), skeleton.rest_versors().end());
  return p;
}

Pose sample(const Skeleton& skeleton, const Clip& clip, double time, BlendMode mode) {
  if (!std::isfinite(time)) throw InvalidInputError("sample: the time is NaN or infinite");
  Pose p = rest_pose(skeleton);
  const double t = std::clamp(time, 0.0, clip.duration);
  std::vector<bool> touched(skeleton.size(), false);
  for (const Channel& c : clip.channels) {
    if (c.joint < 0 || c.joint >= skeleton.size())
      throw InvalidInputError("sample: clip '" + clip.name + "' drives joint " + std::to_string(c.joint) +
                              " outside the skeleton");
    if (c.times.empty()) continue;
    if (c.path == ChannelPath::weights) {
      const std::size_t blocks = c.interpolation == Interpolation::cubic_spline ? 3 : 1;
      if (c.weight_count <= 0 || c.values.size() != c.times.size() * blocks * static_cast<std::size_t>(c.weight_count))
        throw InvalidInputError("sample: clip '" + clip.name + "' has a weights channel of " +
                                std::to_string(c.weight_count) + " weights and " + std::to_string(c.values.size()) +
                                " values");
      p.morph_weights.resize(static_cast<std::size_t>(skeleton.size()));
      evaluate_weights(c, locate(c.times, t), p.morph_weights[static_cast<std::size_t>(c.joint)]);
      continue;
    }
    evaluate(c, locate(c.times, t), mode, p.local[c.joint]);
    touched[c.joint] = true;
  }
  for (int j = 0; j < skeleton.size(); ++j)
    if (touched[j]) p.local_versors[j] = p.local[j].versor();
  return p;
}

void apply_edits(Pose& pose, std::span<const JointEdit> edits) {
  for (const JointEdit& e : edits) {
    if (e.joint < 0 || e.joint >= static_cast<int>(pose.local.size()))
      throw InvalidInputError("pose edit: joint index " + std::to_string(e.joint) + " is not in the skeleton");
    const cga::Rotor<double> r = e.angle == 0 ? cga::Rotor<double>(cga::basis_blade<double, cga::blade::scalar>())
                                              : cga::rotor(Vec3<double>(e.axis), e.angle);
    const cga::Versor<double> edit = cga::similarity(Vec3<double>(e.translation), r, e.scale);
    // Matrix path: compose exactly (keeps any non-uniform rest scale of the joint).
    const Eigen::Matrix4d m = pose.local[e.joint].matrix() * Transform::from_versor(edit).matrix();
    pose.local_versors[e.joint] = cga::Versor<double>(pose.local_versors[e.joint] * edit);
    pose.local[e.joint] = Transform::from_matrix(m);
  }
}

std::vector<cga::Versor<double>> global_versors(const Skeleton& skeleton, const Pose& pose) {
  std::vector<cga::Versor<double>> g(pose.local_versors.size());
  const auto parents = skeleton.parents();
  // At and below a non-uniform scale, composing geometric means drifts even where the global
  // map is a similarity (a parent's stretch of its child's offset is no mean): those joints take
  // the versor nearest their exact global matrix. Similarity rigs never build the matrices.
  std::vector<char> stretched(g.size(), 0);
  std::vector<Eigen::Matrix4d> exact;
  for (std::size_t j = 0; j < g.size(); ++j) {
    const int p = parents[j];
    stretched[j] = !pose.local[j].is_uniform() || (p >= 0 && stretched[static_cast<std::size_t>(p)]);
    if (!stretched[j]) {
      g[j] = p < 0 ? pose.local_versors[j] : cga::Versor<double>(g[p] * pose.local_versors[j]);
      continue;
    }
    if (exact.empty()) exact = global_matrices(skeleton, pose);
    g[j] = nearest_similarity(exact[j]);
  }
  return g;
}

std::vector<Eigen::Matrix4d> global_matrices(const Skeleton& skeleton, const Pose& pose) {
  std::vector<Eigen::Matrix4d> g(pose.local.size());
  const auto parents = skeleton.parents();
  for (std::size_t j = 0; j < g.size(); ++j)
    g[j] = parents[j] < 0 ? pose.local[j].matrix() : Eigen::Matrix4d(g[parents[j]] * pose.local[j].matrix());
  return g;
}

}  // namespace cgamesh::anim
