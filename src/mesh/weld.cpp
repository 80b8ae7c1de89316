#include "cgamesh/mesh/weld.hpp"

#include <cstdint>
#include <cstring>
#include <string>

#include "cgamesh/errors.hpp"

#include "position_welder.hpp"

namespace cgamesh::mesh {

std::size_t PositionHash::operator()(const std::array<float, 3>& p) const noexcept {
  std::array<std::uint32_t, 3> bits;
  std::memcpy(bits.data(), p.data(), sizeof bits);
  return (static_cast<std::size_t>(bits[0]) * 73856093u) ^ (static_cast<std::size_t>(bits[1]) * 19349663u) ^
         (static_cast<std::size_t>(bits[2]) * 83492791u);
}

int PositionWelder::operator()(int v) { return *first_.try_emplace(position_key(positions_, v), v).first; }

std::vector<int> weld_by_position(const RowMatrixXf<3>& positions) {
  PositionWelder weld(positions);
  std::vector<int> out(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) out[static_cast<std::size_t>(i)] = weld(static_cast<int>(i));
  return out;
}

int number_classes(std::span<int> ids) {
  // A representative is its class's first vertex, so it is numbered before its copies.
  int count = 0;
  for (std::size_t v = 0; v < ids.size(); ++v) {
    if (ids[v] < 0 || ids[v] > static_cast<int>(v))
      throw InvalidInputError("number_classes: vertex " + std::to_string(v) + " has representative " +
                              std::to_string(ids[v]) + ", not one of the vertices 0 … " + std::to_string(v));
    ids[v] = ids[v] == static_cast<int>(v) ? count++ : ids[static_cast<std::size_t>(ids[v])];
  }
  return count;
}

}  // namespace cgamesh::mesh
