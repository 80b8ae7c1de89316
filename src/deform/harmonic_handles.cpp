#include "cgamesh/deform/harmonic_handles.hpp"

#include <string>

#include "cgamesh/errors.hpp"

namespace cgamesh::deform {

Eigen::MatrixXd harmonic_coordinates(const mesh::Mesh& mesh, std::span<const std::vector<int>> handles,
                                     const HarmonicOptions& options) {
  if (handles.empty()) throw InvalidInputError("harmonic coordinates: no handle");
  std::vector<int> constrained;
  std::vector<int> owner;
  for (std::size_t j = 0; j < handles.size(); ++j) {
    if (handles[j].empty()) throw InvalidInputError("harmonic coordinates: handle " + std::to_string(j) + " is empty");
    constrained.insert(constrained.end(), handles[j].begin(), handles[j].end());
    owner.insert(owner.end(), handles[j].size(), static_cast<int>(j));
  }
  const HarmonicPrecomputation pre = harmonic_precompute(mesh, constrained, options);
  Eigen::MatrixXd boundary =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(constrained.size()), static_cast<Eigen::Index>(handles.size()));
  for (std::size_t r = 0; r < constrained.size(); ++r) boundary(static_cast<Eigen::Index>(r), owner[r]) = 1.0;
  try {
    return harmonic_solve(pre, boundary);
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(std::string("harmonic coordinates: two handles share a vertex: ") + e.what());
  }
}

MotorBlend bind_harmonic_handles(const mesh::Mesh& mesh, std::span<const std::vector<int>> handles,
                                 std::span<const cga::Versor<double>> rest_keys, const HarmonicOptions& options,
                                 const MotorBlendOptions& blend_options) {
  if (rest_keys.size() != handles.size())
    throw InvalidInputError("harmonic handles: " + std::to_string(rest_keys.size()) + " key motors for " +
                            std::to_string(handles.size()) + " handles");
  return MotorBlend(mesh.positions, harmonic_coordinates(mesh, handles, options), rest_keys, blend_options);
}

}  // namespace cgamesh::deform
