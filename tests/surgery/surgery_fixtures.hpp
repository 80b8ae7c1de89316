#pragma once
// Models the surgery tests share: small hand-made meshes and real models placed in a pose.

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "anim/model_fixtures.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/tear.hpp"
#include "surgery/surgery_checks.hpp"

namespace cgamesh_test {

/// A model with one static mesh and a one-joint skeleton, placed at rest.
inline cgamesh::anim::RiggedModel static_model(cgamesh::mesh::Mesh m) {
  cgamesh::anim::RiggedModel model;
  cgamesh::anim::EditableSkeleton es;
  es.joints.push_back({"root", -1, {}});
  model.skeleton = cgamesh::anim::Skeleton::build(es);
  m.node = 0;
  model.meshes.push_back(std::move(m));
  return model;
}

inline cgamesh::surgery::Placement rest_placement(const cgamesh::anim::RiggedModel& model) {
  return cgamesh::surgery::place(model, cgamesh::anim::rest_pose(model.skeleton));
}

/// The unit cube [0,1]^3, 8 vertices, 12 outward triangles.
inline cgamesh::mesh::Mesh cube() {
  cgamesh::mesh::Mesh m;
  m.name = "cube";
  m.positions.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.positions.row(i) << float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1);
  m.faces.resize(12, 3);
  m.faces << 0, 2, 1, 1, 2, 3,  // z = 0
      4, 5, 6, 5, 7, 6,         // z = 1
      0, 1, 4, 1, 5, 4,         // y = 0
      2, 6, 3, 3, 6, 7,         // y = 1
      0, 4, 2, 2, 4, 6,         // x = 0
      1, 3, 5, 3, 7, 5;         // x = 1
  return m;
}

/// A flat n×n grid of unit squares in z = 0.
inline cgamesh::mesh::Mesh grid(int n) {
  cgamesh::mesh::Mesh m;
  m.name = "grid";
  m.positions.resize((n + 1) * (n + 1), 3);
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.positions.row(y * (n + 1) + x) << float(x), float(y), 0.0f;
  m.faces.resize(2 * n * n, 3);
  int f = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      m.faces.row(f++) << a, b, d;
      m.faces.row(f++) << a, d, c;
    }
  return m;
}

struct Subject {
  std::string name;
  cgamesh::anim::RiggedModel model;
  cgamesh::surgery::Placement placement;
  bool closed = false;
  /// The surface crosses itself somewhere (arm_16k does): some sections cannot be capped.
  bool self_intersecting = false;
};

/// Real models: CesiumMan placed mid-animation (the tool meets the posed body), RiggedFigure at
/// rest, and two closed static meshes for caps.
inline const std::vector<Subject>& subjects() {
  static const std::vector<Subject> all = [] {
    std::vector<Subject> out;
    const auto add = [&](const std::string& name, const std::filesystem::path& path, double time, bool closed,
                         bool self_intersecting = false) {
      Subject s{name, cgamesh::io::load_model(path), {}, closed, self_intersecting};
      const cgamesh::anim::Pose pose = s.model.clips.empty() || time < 0
                                  ? cgamesh::anim::rest_pose(s.model.skeleton)
                                  : cgamesh::anim::sample(s.model.skeleton, s.model.clips[0], time, cgamesh::anim::BlendMode::format);
      s.placement = cgamesh::surgery::place(s.model, pose);
      out.push_back(std::move(s));
    };
    add("CesiumMan", demo_model(), 0.5, false);
    add("RiggedFigure", asset("RiggedFigure.glb"), -1, false);
    add("spot", asset("spot.obj"), -1, true);
    add("arm_16k", asset("arm_16k.ply"), -1, true, true);
    return out;
  }();
  return all;
}

inline double model_diagonal(const Subject& s) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const Points& p : s.placement.positions) {
    lo = lo.cwiseMin(p.colwise().minCoeff().transpose());
    hi = hi.cwiseMax(p.colwise().maxCoeff().transpose());
  }
  return static_cast<double>((hi - lo).norm());
}

/// The middle of the placed vertices at 60% of the height (y): inside the torso of a standing
/// figure such as CesiumMan.
inline Eigen::Vector3d torso_centre(const Points& placed) {
  const float lo = placed.col(1).minCoeff(), hi = placed.col(1).maxCoeff(), y = lo + 0.6f * (hi - lo);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (Eigen::Index v = 0; v < placed.rows(); ++v)
    if (std::abs(placed(v, 1) - y) < 0.02f * (hi - lo)) {
      sum += placed.row(v).cast<double>().transpose();
      ++n;
    }
  return sum / n;
}

/// A stroke over the placed surface: the blade stands on the surface along its normal at a
/// random point, then moves by `reach` along the surface, for `steps` steps.
inline std::vector<cgamesh::surgery::Scalpel> random_stroke(const Subject& s, std::mt19937& rng, int steps, double reach) {
  const cgamesh::mesh::Mesh& m = s.model.meshes[0];
  const Points& p = s.placement.positions[0];
  std::uniform_int_distribution<Eigen::Index> pick(0, m.face_count() - 1);
  const Eigen::Index f = pick(rng);
  const Eigen::Vector3d a = p.row(m.faces(f, 0)).cast<double>(), b = p.row(m.faces(f, 1)).cast<double>(),
                        c = p.row(m.faces(f, 2)).cast<double>();
  std::uniform_real_distribution<double> u(0.05, 0.9);
  const double r = u(rng), q = u(rng) * (1 - r);
  Eigen::Vector3d x = a + r * (b - a) + q * (c - a);
  Eigen::Vector3d n = (b - a).cross(c - a);
  if (n.norm() == 0) n = Eigen::Vector3d::UnitZ();
  n.normalize();
  Eigen::Vector3d dir = random_direction(rng);
  dir = (dir - dir.dot(n) * n).normalized();
  const double depth = 0.02 * model_diagonal(s);
  std::vector<cgamesh::surgery::Scalpel> out;
  for (int i = 0; i < steps; ++i) {
    out.push_back({x + depth * n, x - depth * n});
    x += reach / steps * dir;
  }
  return out;
}

}  // namespace cgamesh_test
