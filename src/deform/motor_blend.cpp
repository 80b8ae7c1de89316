#include "cgamesh/deform/motor_blend.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cgamesh/errors.hpp"

#include "../parallel_for.hpp"

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

std::vector<cga::SimilarityGenerator<double>> similarity_logs(std::span<const cga::Versor<double>> keys) {
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

namespace {

cga::SimilarityGenerator<double> blended_generator(const double* w,
                                                   std::span<const cga::SimilarityGenerator<double>> logs) noexcept {
  cga::SimilarityGenerator<double> sum;
  for (std::size_t j = 0; j < logs.size(); ++j) sum += logs[j] * w[j];
  return sum;
}

}  // namespace

MotorBlend::MotorBlend(const mesh::RowMatrixXf<3>& rest, WeightMatrix weights,
                       std::span<const cga::Versor<double>> rest_keys, const MotorBlendOptions& options)
    : weights_(std::move(weights)), bound_(rest.rows(), 3), threads_(options.threads) {
  if (weights_.rows() != rest.rows())
    throw InvalidInputError("motor blend: the weights have " + std::to_string(weights_.rows()) +
                            " rows, expected #V = " + std::to_string(rest.rows()));
  bind(rest, rest_keys);
}

MotorBlend::MotorBlend(const mesh::RowMatrixXf<3>& rest, WeightMatrix weights, std::vector<int> rows,
                       std::span<const cga::Versor<double>> rest_keys, const MotorBlendOptions& options)
    : weights_(std::move(weights)), rows_(std::move(rows)), bound_(rest.rows(), 3), threads_(options.threads) {
  if (static_cast<Eigen::Index>(rows_.size()) != rest.rows())
    throw InvalidInputError("motor blend: " + std::to_string(rows_.size()) + " weight rows given for " +
                            std::to_string(rest.rows()) + " vertices");
  for (const int r : rows_)
    if (r < 0 || r >= weights_.rows())
      throw InvalidInputError("motor blend: weight row " + std::to_string(r) + " out of range");
  bind(rest, rest_keys);
}

void MotorBlend::bind(const mesh::RowMatrixXf<3>& rest, std::span<const cga::Versor<double>> rest_keys) {
  if (rest_keys.empty()) throw InvalidInputError("motor blend: no key motors");
  if (weights_.cols() != static_cast<Eigen::Index>(rest_keys.size()))
    throw InvalidInputError("motor blend: the weights have " + std::to_string(weights_.cols()) + " columns, expected " +
                            std::to_string(rest_keys.size()) + " (one per key)");
  if (!weights_.allFinite()) throw InvalidInputError("motor blend: a weight is NaN or infinite");
  const auto logs = similarity_logs(rest_keys);
  // p' = ~M p M is the inverse map: A^-1 (p - b), with A = s R.
  const auto inverse = [&](const Eigen::Matrix<double, 3, 4>& m, Eigen::Index i) {
    const Eigen::Vector3d p = rest.row(i).transpose().cast<double>() - m.col(3);
    bound_.row(i) = (m.leftCols<3>().inverse() * p).transpose().cast<float>();
  };
  if (rows_.empty()) {
    for (Eigen::Index i = 0; i < rest.rows(); ++i)
      inverse(similarity_exp_affine(blended_generator(weights_.row(i).data(), logs)), i);
    return;
  }
  std::vector<Eigen::Matrix<double, 3, 4>> maps(static_cast<std::size_t>(weights_.rows()));
  for (Eigen::Index r = 0; r < weights_.rows(); ++r)
    maps[static_cast<std::size_t>(r)] = similarity_exp_affine(blended_generator(weights_.row(r).data(), logs));
  for (Eigen::Index i = 0; i < rest.rows(); ++i) inverse(maps[static_cast<std::size_t>(row(i))], i);
}

std::vector<cga::SimilarityGenerator<double>> MotorBlend::key_logs(std::span<const cga::Versor<double>> keys) const {
  if (static_cast<Eigen::Index>(keys.size()) != key_count())
    throw InvalidInputError("motor blend: " + std::to_string(keys.size()) + " keys given, bound to " +
                            std::to_string(key_count()));
  return similarity_logs(keys);
}

void MotorBlend::deform_range(std::span<const cga::SimilarityGenerator<double>> logs, Eigen::Index begin,
                              Eigen::Index end, mesh::RowMatrixXf<3>& out) const noexcept {
  for (Eigen::Index i = begin; i < end; ++i) {
    const Eigen::Matrix<double, 3, 4> m = similarity_exp_affine(blended_generator(weights_.row(row(i)).data(), logs));
    out.row(i) = (m.leftCols<3>() * bound_.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  }
}

std::vector<Eigen::Matrix<float, 3, 4>> MotorBlend::row_maps(
    std::span<const cga::SimilarityGenerator<double>> logs) const {
  std::vector<Eigen::Matrix<float, 3, 4>> maps(static_cast<std::size_t>(weights_.rows()));
  detail::parallel_for(weights_.rows(), threads_, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index r = begin; r < end; ++r)
      maps[static_cast<std::size_t>(r)] =
          similarity_exp_affine(blended_generator(weights_.row(r).data(), logs)).cast<float>();
  });
  return maps;
}

void MotorBlend::deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out) const {
  const auto logs = key_logs(keys);
  const Eigen::Index n = vertex_count();
  out.resize(n, 3);
  if (rows_.empty()) {
    detail::parallel_for(n, threads_,
                         [&](Eigen::Index begin, Eigen::Index end) { deform_range(logs, begin, end, out); });
    return;
  }
  const auto maps = row_maps(logs);
  detail::parallel_for(n, threads_, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) {
      const Eigen::Matrix<float, 3, 4>& m = maps[static_cast<std::size_t>(rows_[static_cast<std::size_t>(i)])];
      out.row(i) = (m.leftCols<3>() * bound_.row(i).transpose() + m.col(3)).transpose();
    }
  });
}

}  // namespace cgamesh::deform
