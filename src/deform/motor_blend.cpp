#include "cgamesh/deform/motor_blend.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>
#include <string>
#include <thread>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cgamesh/errors.hpp"

namespace cgamesh::deform {

Eigen::Matrix<double, 3, 4> similarity_exp_affine(const cga::SimilarityGenerator<double>& b) noexcept {
  namespace bl = cga::blade;
  const double b12 = b.get<bl::e12>(), b13 = b.get<bl::e13>(), b23 = b.get<bl::e23>();
  const double theta = std::sqrt(b12 * b12 + b13 * b13 + b23 * b23);  // half the rotation angle
  const double s = std::sin(theta), c = std::cos(theta);
  const double sinc = theta < 1e-4 ? 1.0 - theta * theta / 6.0 : s / theta;
  // The rotor cos(theta) + sinc (b12 e12 + b13 e13 + b23 e23) as the quaternion (w, x, y, z).
  const double qw = c, qx = -sinc * b23, qy = sinc * b13, qz = -sinc * b12;
  const Eigen::Vector3d w(-2.0 * b23, 2.0 * b13, -2.0 * b12);  // rotation vector, |w| = 2 theta
  const Eigen::Vector3d v(-2.0 * b.get<bl::e1inf>(), -2.0 * b.get<bl::e2inf>(), -2.0 * b.get<bl::e3inf>());
  const double lambda = -2.0 * b.get<bl::info>();  // log of the scale
  // t = F(A) v with F(A) = (e^A - Id) A^-1 (cga/exp_log.hpp): c1 v + c2 (w.v) w + c3 w x v.
  double c1 = 0, c2 = 0, c3 = 0;
  if (lambda == 0.0) {
    // f(i phi) = sin(phi)/phi + i (1 - cos(phi))/phi from the half-angle sine and cosine.
    c1 = c * sinc;
    c3 = 0.5 * sinc * sinc;
    c2 = theta < 1e-2 ? 1.0 / 6.0 - theta * theta / 30.0 : (1.0 - c1) / (4.0 * theta * theta);
  } else {
    const double phi = 2.0 * theta;
    const auto k = cga::detail::screw_coefficients(cga::detail::expm1_over_z(std::complex<double>(lambda)).real(),
                                                   cga::detail::expm1_over_z(std::complex<double>(lambda, phi)), phi);
    c1 = k.c1, c2 = k.c2, c3 = k.c3;
  }
  const double scale = std::exp(lambda);
  Eigen::Matrix<double, 3, 4> m;
  const double xx = qx * qx, yy = qy * qy, zz = qz * qz, xy = qx * qy, xz = qx * qz, yz = qy * qz;
  const double wx = qw * qx, wy = qw * qy, wz = qw * qz;
  m << 1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy), 0,  //
      2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx), 0,   //
      2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy), 0;
  m.leftCols<3>() *= scale;
  m.col(3) = c1 * v + c2 * w.dot(v) * w + c3 * w.cross(v);
  return m;
}

namespace {

std::vector<cga::SimilarityGenerator<double>> logs_of(std::span<const cga::Versor<double>> keys) {
  std::vector<cga::SimilarityGenerator<double>> logs;
  logs.reserve(keys.size());
  for (std::size_t j = 0; j < keys.size(); ++j) {
    try {
      logs.push_back(cga::log(keys[j]));
    } catch (const InvalidInputError& e) {
      throw InvalidInputError("key " + std::to_string(j) + ": " + e.what());
    }
  }
  return logs;
}

cga::SimilarityGenerator<double> blended_generator(const double* w, std::span<const cga::SimilarityGenerator<double>> logs) noexcept {
  cga::SimilarityGenerator<double> sum;
  for (std::size_t j = 0; j < logs.size(); ++j) sum += logs[j] * w[j];
  return sum;
}

}  // namespace

MotorBlend::MotorBlend(const mesh::RowMatrixXf<3>& rest, WeightMatrix weights,
                       std::span<const cga::Versor<double>> rest_keys, const MotorBlendOptions& options)
    : weights_(std::move(weights)), bound_(rest.rows(), 3), threads_(options.threads) {
  if (rest_keys.empty()) throw InvalidInputError("motor blend: no key motors");
  if (weights_.rows() != rest.rows() || weights_.cols() != static_cast<Eigen::Index>(rest_keys.size()))
    throw InvalidInputError("motor blend: the weights are " + std::to_string(weights_.rows()) + " x " +
                            std::to_string(weights_.cols()) + ", expected #V x #keys = " + std::to_string(rest.rows()) +
                            " x " + std::to_string(rest_keys.size()));
  if (!weights_.allFinite()) throw InvalidInputError("motor blend: a weight is NaN or infinite");
  const auto logs = logs_of(rest_keys);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Eigen::Matrix<double, 3, 4> m = similarity_exp_affine(blended_generator(weights_.row(i).data(), logs));
    // p' = ~M p M is the inverse map: A^-1 (p - b), with A = s R.
    const Eigen::Vector3d p = rest.row(i).transpose().cast<double>() - m.col(3);
    bound_.row(i) = (m.leftCols<3>().inverse() * p).transpose().cast<float>();
  }
}

std::vector<cga::SimilarityGenerator<double>> MotorBlend::key_logs(std::span<const cga::Versor<double>> keys) const {
  if (static_cast<Eigen::Index>(keys.size()) != key_count())
    throw InvalidInputError("motor blend: " + std::to_string(keys.size()) + " keys given, bound to " +
                            std::to_string(key_count()));
  return logs_of(keys);
}

void MotorBlend::deform_range(std::span<const cga::SimilarityGenerator<double>> logs, Eigen::Index begin,
                              Eigen::Index end, mesh::RowMatrixXf<3>& out) const noexcept {
  for (Eigen::Index i = begin; i < end; ++i) {
    const Eigen::Matrix<double, 3, 4> m = similarity_exp_affine(blended_generator(weights_.row(i).data(), logs));
    out.row(i) = (m.leftCols<3>() * bound_.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  }
}

void MotorBlend::deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out) const {
  const auto logs = key_logs(keys);
  const Eigen::Index n = vertex_count();
  out.resize(n, 3);
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // Below a few thousand vertices per thread, starting threads costs more than it saves.
  const int t = static_cast<int>(std::min<Eigen::Index>(threads_ > 0 ? threads_ : hw, std::max<Eigen::Index>(1, n / 4096)));
  std::vector<std::thread> pool;
  for (int k = 1; k < t; ++k)
    pool.emplace_back([&, k] { deform_range(logs, n * k / t, n * (k + 1) / t, out); });
  deform_range(logs, 0, n / t, out);
  for (auto& th : pool) th.join();
}

}  // namespace cgamesh::deform
