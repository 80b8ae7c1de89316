#include "cgamesh/anim/skinning.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unistd.h>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/transform.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/interpolation.hpp"
#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"

#include "../parallel_for.hpp"
#include "packed_palette.hpp"
#include "polar.hpp"
#include "skinning_blocks.hpp"

namespace cgamesh::anim {
namespace {

/// Whether versor v is a motor up to noise: its dilation part within 1e-6 of its size (float
/// keyframes and inverse binds leave a few 1e-7 on rigid rigs).
template <class T>
bool is_motor(const cga::Versor<T>& v) {
  return cga::max_abs(cga::project<cga::kEvenBlades & ~cga::mask::motor>(v)) <= T(1e-6) * cga::max_abs(v);
}

using mesh::Mesh;
using mesh::RowMatrixXf;

/// The rest rows a skinning job reads, vertex i at row i - first: the mesh's own rows (first 0),
/// or the job's rows with the frame's morph targets applied (morph_rows()).
struct RestRows {
  const RowMatrixXf<3>& positions;
  const RowMatrixXf<3>& normals;
  Eigen::Index first = 0;

  [[nodiscard]] Eigen::Vector3f position(Eigen::Index i) const { return positions.row(i - first).transpose(); }
  [[nodiscard]] Eigen::Vector3f normal(Eigen::Index i) const { return normals.row(i - first).transpose(); }
};

/// Global joint of palette entry k, and its inverse bind (identity for a static mesh).
int palette_joint(const Mesh& m, std::size_t k) { return m.skin.empty() ? m.node : m.skin.palette[k]; }
std::size_t palette_size(const Mesh& m) { return m.skin.empty() ? 1 : m.skin.palette.size(); }

/// The exact map M_n B_n of palette entry k as a matrix (globals_matrix has the joint).
Eigen::Matrix4d exact_map(const Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix, std::size_t k) {
  const int j = palette_joint(mesh, k);
  Eigen::Matrix4d m = j < 0 ? Eigen::Matrix4d::Identity() : globals_matrix[static_cast<std::size_t>(j)];
  if (!mesh.skin.empty()) m = m * mesh.skin.inverse_bind[k];
  return m;
}

/// Whether palette entry k maps by similarities: its joint's global matrix and its inverse bind,
/// so that their versors M_n and B_n are exact (global_versors()).
bool similarity_entry(const Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix, std::size_t k) {
  const int j = palette_joint(mesh, k);
  return (j < 0 || is_similarity(globals_matrix[static_cast<std::size_t>(j)])) &&
         (mesh.skin.empty() || is_similarity(mesh.skin.inverse_bind[k]));
}

/// The dual quaternion of m's rigid part and its scale/shear part: m = [R t] [S 0] with R a
/// rotation and S symmetric (polar decomposition; a mirror goes into S).
Eigen::Matrix<float, 8, 1> dual_quaternion(const Eigen::Matrix4d& m, Eigen::Matrix3d& s) {
  Eigen::Matrix3d r;
  detail::rotation_scaling(m.topLeftCorner<3, 3>(), r, s);
  const Eigen::Quaterniond q(r);
  const Eigen::Vector3d t = m.topRightCorner<3, 1>();
  const Eigen::Quaterniond d = Eigen::Quaterniond(0, t.x(), t.y(), t.z()) * q;
  Eigen::Matrix<float, 8, 1> out;
  out << q.coeffs().cast<float>(), (0.5 * d.coeffs()).cast<float>();
  return out;
}

/// The cofactor matrix det(L) L^-T: it maps normals of any invertible L.
Eigen::Matrix3f cofactor(const Eigen::Matrix3f& l) {
  Eigen::Matrix3f cof;
  cof << l.col(1).cross(l.col(2)), l.col(2).cross(l.col(0)), l.col(0).cross(l.col(1));
  return cof;
}

/// Influences of vertex i as (palette entry, weight); a static mesh has one of weight 1.
template <class F>
void for_each_influence(const Mesh& m, Eigen::Index i, F&& f) {
  if (m.skin.empty()) {
    f(0, 1.0f);
    return;
  }
  for (int k = 0; k < 4; ++k) {
    const float w = m.skin.weights(i, k);
    if (w > 0) f(m.skin.joints(i, k), w);
  }
}

/// Blended dual quaternion of vertex i, normalised: rotation q and dual part d.
void blend_dual_quaternion(const Mesh& mesh, const SkinningPalette& p, Eigen::Index i, Eigen::Quaternionf& q,
                           Eigen::Quaternionf& d) {
  Eigen::Matrix<float, 8, 1> b = Eigen::Matrix<float, 8, 1>::Zero();
  const Eigen::Matrix<float, 8, 1>* first = nullptr;
  for_each_influence(mesh, i, [&](int k, float w) {
    const auto& dq = p.dual_quats[k];
    if (!first) first = &dq;
    b += (first->head<4>().dot(dq.head<4>()) < 0 ? -w : w) * dq;
  });
  const float n = b.head<4>().norm();
  q = Eigen::Quaternionf(b[3] / n, b[0] / n, b[1] / n, b[2] / n);
  d = Eigen::Quaternionf(b[7] / n, b[4] / n, b[5] / n, b[6] / n);
}

/// Kavan et al. 2008 two-phase skinning, first phase: Σ w S_n of vertex i (p.scales non-empty).
Eigen::Matrix3f blend_scale(const Mesh& mesh, const SkinningPalette& p, Eigen::Index i) {
  Eigen::Matrix3f s = Eigen::Matrix3f::Zero();
  for_each_influence(mesh, i, [&](int k, float w) { s += w * p.scales[k]; });
  return s;
}

/// Blended versor of vertex i, renormalised (versor skinning).
template <class V>
V blend_versor(const Mesh& mesh, std::span<const V> palette, Eigen::Index i) {
  V v;
  const V* first = nullptr;
  int count = 0;
  for_each_influence(mesh, i, [&](int k, float w) {
    const V& pk = palette[k];
    if (!first) first = &pk;
    ++count;
    // V and -V are the same transform: blend on the side of the first influence.
    v += (cga::scalar_product(*first, cga::reverse(pk)) < 0 ? -w : w) * pk;
  });
  // One influence (weight 1) is already a unit versor.
  return count > 1 ? cga::normalized(v) : v;
}

/// Versor skinning: per vertex, blend the palette versors, renormalise, one sandwich.
template <class V>
void skin_blended(const Mesh& mesh, const RestRows& rest, std::span<const V> palette, Eigen::Index begin,
                  Eigen::Index end, RowMatrixXf<3>& out) {
  for (Eigen::Index i = begin; i < end; ++i) {
    const cga::Vector<float> y = cga::unit_sandwich(blend_versor(mesh, palette, i), cga::up(rest.position(i)));
    const float inv = 1.0f / y.get<cga::blade::eo>();
    out.row(i) << y[0] * inv, y[1] * inv, y[2] * inv;
  }
}

/// Versor skinning of normals: the Euclidean part of the blended versor's sandwich of n.
template <class V>
void skin_blended_normals(const Mesh& mesh, const RestRows& rest, std::span<const V> palette, Eigen::Index begin,
                          Eigen::Index end, RowMatrixXf<3>& out) {
  for (Eigen::Index i = begin; i < end; ++i) {
    const Eigen::Vector3f r = rest.normal(i);
    const cga::Vector<float> y =
        cga::unit_sandwich(blend_versor(mesh, palette, i), cga::euclidean<float>(r.x(), r.y(), r.z()));
    out.row(i) << y[0], y[1], y[2];
  }
}

/// The scalar kernel, positions: one vertex at a time.
void skin_positions(const Mesh& mesh, const RestRows& rest, const SkinningPalette& p, Eigen::Index begin,
                    Eigen::Index end, RowMatrixXf<3>& out) {
  switch (p.mode) {
    case SkinningMode::cga:
    case SkinningMode::matrix:
      for (Eigen::Index i = begin; i < end; ++i) {
        const Eigen::Vector3f x = rest.position(i);
        Eigen::Vector3f y = Eigen::Vector3f::Zero();
        for_each_influence(mesh, i, [&](int k, float w) {
          const auto& a = p.affine[k];
          y += w * (a.leftCols<3>() * x + a.col(3));
        });
        out.row(i) = y.transpose();
      }
      return;
    case SkinningMode::versor:
      if (!p.motors.empty())
        skin_blended(mesh, rest, std::span(p.motors), begin, end, out);
      else
        skin_blended(mesh, rest, std::span(p.versors), begin, end, out);
      return;
    case SkinningMode::dqs:
      for (Eigen::Index i = begin; i < end; ++i) {
        Eigen::Quaternionf q, d;
        blend_dual_quaternion(mesh, p, i, q, d);
        const Eigen::Vector3f t = 2.0f * (d * q.conjugate()).vec();
        Eigen::Vector3f x = rest.position(i);
        if (!p.scales.empty()) x = blend_scale(mesh, p, i) * x;
        out.row(i) = (q * x + t).transpose();
      }
      return;
  }
}

/// The scalar kernel, normals (the mesh has #V normals).
void skin_normal_rows(const Mesh& mesh, const RestRows& rest, const SkinningPalette& p, Eigen::Index begin,
                      Eigen::Index end, RowMatrixXf<3>& out) {
  switch (p.mode) {
    case SkinningMode::cga:
    case SkinningMode::matrix:
      for (Eigen::Index i = begin; i < end; ++i) {
        Eigen::Matrix3f l = Eigen::Matrix3f::Zero();
        for_each_influence(mesh, i, [&](int k, float w) { l += w * p.affine[k].leftCols<3>(); });
        out.row(i) = (cofactor(l) * rest.normal(i)).transpose();
      }
      break;
    case SkinningMode::versor:
      if (!p.motors.empty())
        skin_blended_normals(mesh, rest, std::span(p.motors), begin, end, out);
      else
        skin_blended_normals(mesh, rest, std::span(p.versors), begin, end, out);
      break;
    case SkinningMode::dqs:
      for (Eigen::Index i = begin; i < end; ++i) {
        Eigen::Quaternionf q, d;
        blend_dual_quaternion(mesh, p, i, q, d);
        Eigen::Vector3f n = rest.normal(i);
        if (!p.scales.empty()) n = cofactor(blend_scale(mesh, p, i)) * n;
        out.row(i) = (q * n).transpose();
      }
      break;
  }
  for (Eigen::Index i = begin; i < end; ++i) {
    const float len = out.row(i).norm();
    if (len > 0 && std::isfinite(len))
      out.row(i) /= len;
    else
      out.row(i) = rest.normal(i).transpose();
  }
}

/// Kernel `k` resolved (automatic: the fastest available); throws when it cannot run here.
SkinningKernel resolve(SkinningKernel k) {
  if (k == SkinningKernel::automatic)
    return detail::cpu_has_avx512()     ? SkinningKernel::avx512
           : detail::cpu_has_avx2_fma() ? SkinningKernel::avx2
                                        : SkinningKernel::vector;
  if (!kernel_available(k))
    throw InvalidInputError(k == SkinningKernel::avx2
                                ? "skinning: this processor has no AVX2 and FMA for the avx2 kernel"
                                : "skinning: this processor has no AVX-512 (F, VL, DQ, BW) for the avx512 kernel");
  return k;
}

/// The checks of a skinning job, so that no kernel reads or writes outside its arrays.
void validate(const Mesh& mesh, const SkinningPalette& p, Eigen::Index begin, Eigen::Index end,
              const RowMatrixXf<3>& positions, const RowMatrixXf<3>* normals) {
  const Eigen::Index n = mesh.vertex_count();
  const auto fail = [&mesh](const std::string& what) {
    throw InvalidInputError("skinning: mesh '" + mesh.name + "': " + what);
  };
  if (begin < 0 || begin > end || end > n)
    fail("vertex range [" + std::to_string(begin) + ", " + std::to_string(end) + ") outside its " + std::to_string(n) +
         " vertices");
  if (positions.rows() != n)
    fail("the output has " + std::to_string(positions.rows()) + " rows for " + std::to_string(n) + " vertices");
  if (normals && (mesh.normals.rows() != n || normals->rows() != n))
    fail(std::to_string(mesh.normals.rows()) + " normals and " + std::to_string(normals->rows()) + " output rows for " +
         std::to_string(n) + " vertices");
  const std::size_t packed = detail::PackedPalette::entries(p).size();
  const auto stride = static_cast<std::size_t>(detail::PackedPalette::stride(p));
  if (packed != stride * palette_size(mesh))
    fail("the palette has " + std::to_string(stride > 0 ? packed / stride : 0) + " entries, the mesh uses " +
         std::to_string(palette_size(mesh)) + " (a palette made for another mesh?)");
}

}  // namespace

std::size_t streaming_bytes() noexcept {
  static const std::size_t bytes = [] {
#if defined(_SC_LEVEL3_CACHE_SIZE)
    for (const int level : {_SC_LEVEL4_CACHE_SIZE, _SC_LEVEL3_CACHE_SIZE, _SC_LEVEL2_CACHE_SIZE})
      if (const long size = sysconf(level); size > 0) return static_cast<std::size_t>(size);
#endif
    return kStreamingBytes;
  }();
  return bytes;
}

bool kernel_available(SkinningKernel kernel) noexcept {
  switch (kernel) {
    case SkinningKernel::automatic:
    case SkinningKernel::scalar:
    case SkinningKernel::vector:
      return true;
    case SkinningKernel::avx2:
      return detail::cpu_has_avx2_fma();
    case SkinningKernel::avx512:
      return detail::cpu_has_avx512();
  }
  return false;
}

SkinningPalette make_palette(const Mesh& mesh, std::span<const cga::Versor<double>> globals_cga,
                             std::span<const Eigen::Matrix4d> globals_matrix, SkinningMode mode,
                             std::span<const float> morph_weights) {
  SkinningPalette p;
  p.mode = mode;
  if (morphs(morph_weights)) {
    check_morph_weights(mesh, morph_weights);
    p.morph_weights.assign(morph_weights.begin(), morph_weights.end());
  }
  const std::size_t n = palette_size(mesh);
  const bool uses_cga = mode == SkinningMode::cga || mode == SkinningMode::versor;
  // Built every frame: one allocation per array, not a growth sequence.
  if (mode == SkinningMode::cga || mode == SkinningMode::matrix) p.affine.reserve(n);
  if (mode == SkinningMode::versor) p.versors.reserve(n);
  if (mode == SkinningMode::dqs) {
    p.dual_quats.reserve(n);
    p.scales.reserve(n);
  }
  detail::PackedPalette::reserve(p, n);
  // cga reads the matrices too, for the entries no versor holds.
  const std::size_t count = mode == SkinningMode::cga ? std::min(globals_cga.size(), globals_matrix.size())
                            : uses_cga                ? globals_cga.size()
                                                      : globals_matrix.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int j = palette_joint(mesh, k);
    if (j >= static_cast<int>(count))
      throw InvalidInputError("skinning: mesh '" + mesh.name + "' uses joint " + std::to_string(j) +
                              " but the pose has " + std::to_string(count));
    if (mode == SkinningMode::cga && !similarity_entry(mesh, globals_matrix, k)) {
      // Non-uniform scale or shear: no versor holds M_n B_n, its exact matrix does.
      p.affine.push_back(exact_map(mesh, globals_matrix, k).topRows<3>().cast<float>());
      continue;
    }
    if (uses_cga) {
      const cga::Versor<double> global =
          j < 0 ? cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()) : globals_cga[j];
      const bool skinned = !mesh.skin.empty();
      // Eq. (17)'s map of M_n B_n; with motors (no dilation) the product runs on 8 coefficients
      // instead of 16, and the map is the rotor's sandwiches and the translator's offset.
      if (mode == SkinningMode::cga && is_motor(global) && (!skinned || is_motor(mesh.skin.inverse_bind_versors[k]))) {
        cga::Motor<double> m = cga::project<cga::mask::motor>(global);
        if (skinned) m = cga::Motor<double>(m * cga::project<cga::mask::motor>(mesh.skin.inverse_bind_versors[k]));
        p.affine.push_back(cga::motor_affine_matrix(m).cast<float>());
        continue;
      }
      cga::Versor<double> v = global;
      if (skinned) v = cga::Versor<double>(v * mesh.skin.inverse_bind_versors[k]);
      if (mode == SkinningMode::cga) {
        p.affine.push_back(cga::PointMap<double>(v).affine_matrix().cast<float>());
      } else {
        cga::Versor<float> vf;
        for (std::size_t c = 0; c < cga::Versor<float>::size; ++c) vf[c] = static_cast<float>(v[c]);
        p.versors.push_back(vf);
      }
    } else {
      const Eigen::Matrix4d m = exact_map(mesh, globals_matrix, k);
      if (mode == SkinningMode::matrix)
        p.affine.push_back(m.topRows<3>().cast<float>());
      else {
        Eigen::Matrix3d s;
        p.dual_quats.push_back(dual_quaternion(m, s));
        p.scales.push_back(s.cast<float>());
      }
    }
  }
  // Rigid joints: the first phase is the identity, skip it. Polar factors of float inverse binds
  // are a few 1e-7 off the identity on rigid rigs (CesiumMan: up to 1.7e-6): noise, not scale.
  if (std::all_of(p.scales.begin(), p.scales.end(), [](const Eigen::Matrix3f& s) { return s.isIdentity(1e-5f); }))
    p.scales.clear();
  // Without dilations every palette versor is a motor: blend 8 coefficients instead of 16.
  if (mode == SkinningMode::versor) {
    const bool rigid = std::all_of(p.versors.begin(), p.versors.end(), is_motor<float>);
    if (rigid)
      for (const cga::Versor<float>& v : p.versors) p.motors.push_back(cga::project<cga::mask::motor>(v));
  }
  detail::PackedPalette::pack(p);
  return p;
}

bool maps_by_similarities(const Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix) {
  for (std::size_t k = 0; k < palette_size(mesh); ++k) {
    const int j = palette_joint(mesh, k);
    if (j >= static_cast<int>(globals_matrix.size()))
      throw InvalidInputError("skinning: mesh '" + mesh.name + "' uses joint " + std::to_string(j) +
                              " but the pose has " + std::to_string(globals_matrix.size()));
    if (!similarity_entry(mesh, globals_matrix, k)) return false;
  }
  return true;
}

double exact_displacement(const Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix,
                          const RowMatrixXf<3>& positions, std::span<const float> morph_weights) {
  if (positions.rows() != mesh.vertex_count())
    throw InvalidInputError("skinning: mesh '" + mesh.name + "': " + std::to_string(positions.rows()) +
                            " positions for " + std::to_string(mesh.vertex_count()) + " vertices");
  const RowMatrixXf<3> exact = skin(mesh, make_palette(mesh, {}, globals_matrix, SkinningMode::matrix, morph_weights));
  double worst = 0;
  for (Eigen::Index i = 0; i < exact.rows(); ++i)
    worst = std::max(worst, static_cast<double>((positions.row(i) - exact.row(i)).norm()));
  return worst;
}

namespace {

/// skin_range() reading the rest rows `rest` (the mesh's, or the job's morphed rows).
void skin_rows(const Mesh& mesh, const RestRows& rest, const SkinningPalette& p, Eigen::Index begin, Eigen::Index end,
               RowMatrixXf<3>& positions, RowMatrixXf<3>* normals, SkinningKernel kernel, SkinningStores stores) {
  kernel = resolve(kernel);
  normals = normals && mesh.normals.rows() > 0 ? normals : nullptr;
  validate(mesh, p, begin, end, positions, normals);
  if (kernel != SkinningKernel::scalar) {
    const detail::BlockKernel blocks = kernel == SkinningKernel::avx512 ? detail::skin_blocks_avx512
                                       : kernel == SkinningKernel::avx2 ? detail::skin_blocks_avx2
                                                                        : detail::skin_blocks_vector;
    // Decided on the whole mesh, so that every job of a frame stores alike: per vertex its rest
    // position, 4 joints, 4 weights and posed position (and its normal in and out).
    const std::size_t bytes = static_cast<std::size_t>(mesh.vertex_count()) * (normals ? 72 : 48);
    const bool streaming =
        stores == SkinningStores::streaming || (stores == SkinningStores::automatic && bytes > streaming_bytes());
    const detail::BlockJob job{&mesh,
                               &p,
                               rest.positions.data(),
                               normals ? rest.normals.data() : nullptr,
                               rest.first,
                               positions.data(),
                               normals ? normals->data() : nullptr,
                               streaming};
    // A block a lane cannot do runs one vertex at a time (which reports the problem).
    for (Eigen::Index stop; (stop = blocks(job, begin, end)) < end - (end - begin) % 8;) {
      skin_positions(mesh, rest, p, stop, stop + 8, positions);
      if (normals) skin_normal_rows(mesh, rest, p, stop, stop + 8, *normals);
      begin = stop + 8;
    }
    begin = end - (end - begin) % 8;
  }
  skin_positions(mesh, rest, p, begin, end, positions);
  if (normals) skin_normal_rows(mesh, rest, p, begin, end, *normals);
}

}  // namespace

void skin_range(const Mesh& mesh, const SkinningPalette& p, Eigen::Index begin, Eigen::Index end,
                RowMatrixXf<3>& positions, RowMatrixXf<3>* normals, SkinningKernel kernel, SkinningStores stores) {
  if (p.morph_weights.empty()) {
    skin_rows(mesh, {mesh.positions, mesh.normals}, p, begin, end, positions, normals, kernel, stores);
    return;
  }
  // The job morphs its own rows only (glTF's order: morph, then skin).
  RowMatrixXf<3> rest_positions, rest_normals;
  morph_rows(mesh, p.morph_weights, begin, end, rest_positions, normals ? &rest_normals : nullptr);
  skin_rows(mesh, {rest_positions, rest_normals, begin}, p, begin, end, positions, normals, kernel, stores);
}

Eigen::Matrix<double, 3, 4> blended_affine(const Mesh& mesh, const SkinningPalette& palette, Eigen::Index i) {
  Eigen::Matrix<double, 3, 4> a = Eigen::Matrix<double, 3, 4>::Zero();
  for_each_influence(mesh, i, [&](int k, float w) { a += static_cast<double>(w) * palette.affine[k].cast<double>(); });
  return a;
}

void skin_into(const Mesh& mesh, const SkinningPalette& palette, RowMatrixXf<3>& positions, RowMatrixXf<3>* normals,
               const SkinningOptions& options) {
  if (mesh.normals.rows() != 0 && mesh.normals.rows() != mesh.vertex_count())
    throw InvalidInputError("skinning: mesh '" + mesh.name + "' has " + std::to_string(mesh.normals.rows()) +
                            " normals for " + std::to_string(mesh.vertex_count()) + " vertices");
  const SkinningKernel kernel = resolve(options.kernel);
  if (positions.rows() != mesh.vertex_count()) positions.resize(mesh.vertex_count(), 3);
  if (normals && normals->rows() != mesh.normals.rows()) normals->resize(mesh.normals.rows(), 3);
  detail::parallel_for(mesh.vertex_count(), options.threads, [&](Eigen::Index begin, Eigen::Index end) {
    skin_range(mesh, palette, begin, end, positions, normals, kernel, options.stores);
  });
}

RowMatrixXf<3> skin(const Mesh& mesh, const SkinningPalette& palette, int threads) {
  RowMatrixXf<3> out;
  skin_into(mesh, palette, out, nullptr, {.threads = threads});
  return out;
}

RowMatrixXf<3> skin_normals(const Mesh& mesh, const SkinningPalette& palette, int threads) {
  RowMatrixXf<3> positions, normals;
  skin_into(mesh, palette, positions, &normals, {.threads = threads});
  return normals;
}

RowMatrixXf<3> skin_cga_reference(const Mesh& mesh, std::span<const cga::Versor<double>> globals_cga) {
  RowMatrixXf<3> out(mesh.vertex_count(), 3);
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i) {
    const cga::Vector<double> x = cga::up(cga::Vec3<double>(mesh.positions.row(i).transpose().cast<double>()));
    cga::Vec3<double> y = cga::Vec3<double>::Zero();
    for_each_influence(mesh, i, [&](int k, float w) {
      const int j = palette_joint(mesh, static_cast<std::size_t>(k));
      cga::Versor<double> v =
          j < 0 ? cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()) : globals_cga[j];
      if (!mesh.skin.empty()) v = cga::Versor<double>(v * mesh.skin.inverse_bind_versors[k]);
      y += static_cast<double>(w) * cga::down(cga::sandwich(v, x));
    });
    out.row(i) = y.transpose().cast<float>();
  }
  return out;
}

}  // namespace cgamesh::anim

namespace cgamesh::detail {

void PackedPalette::pack(anim::SkinningPalette& p) {
  const auto append = [&p](const auto& coefficients, int count) {
    for (int c = 0; c < count; ++c) p.packed_.push_back(static_cast<float>(coefficients[c]));
  };
  switch (p.mode) {
    case anim::SkinningMode::cga:
    case anim::SkinningMode::matrix:
      p.packed_stride_ = 16;
      for (const auto& a : p.affine)
        for (int c = 0; c < 4; ++c) {
          append(a.col(c), 3);
          p.packed_.push_back(0.0f);
        }
      break;
    case anim::SkinningMode::versor:
      if (!p.motors.empty()) {
        p.packed_stride_ = 8;
        for (const auto& m : p.motors) append(m, 8);
      } else {
        p.packed_stride_ = 16;
        for (const auto& v : p.versors) append(v, 16);
      }
      break;
    case anim::SkinningMode::dqs:
      p.packed_stride_ = p.scales.empty() ? 8 : 17;
      for (std::size_t k = 0; k < p.dual_quats.size(); ++k) {
        append(p.dual_quats[k], 8);
        if (!p.scales.empty()) append(p.scales[k].data(), 9);
      }
      break;
  }
}

}  // namespace cgamesh::detail
