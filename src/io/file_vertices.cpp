#include "file_vertices.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "../flat_map.hpp"
#include "gltf_extras_reader.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "cgamesh/io/obj_reader.hpp"

namespace cgamesh::io::detail {
namespace {

/// The vertex count a PLY header declares, if it can be read.
std::optional<long long> ply_vertex_count(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key, name;
    long long count = -1;
    words >> key;
    if (key == "end_header") break;
    if (key == "element" && (words >> name >> count) && name == "vertex" && count >= 0) return count;
  }
  return std::nullopt;
}

/// The positions of an OBJ file's `v` lines, in order (a line whose numbers cannot be read
/// keeps its place, as NaN, so that later lines keep their numbers).
mesh::RowMatrixXf<3> obj_positions(const std::filesystem::path& path) {
  return read_obj(path, {.strict = false, .what = "OBJ"}).vertices.cast<float>();
}

/// Nearest-point lookup among the file's vertices on a grid of cells of twice the tolerance.
class PositionMatcher {
 public:
  explicit PositionMatcher(const mesh::RowMatrixXf<3>& file)
      : file_(file), next_(static_cast<std::size_t>(file.rows()), -1) {
    for (Eigen::Index v = 0; v < file.rows(); ++v)
      if (file.row(v).allFinite()) largest_ = std::max(largest_, file.row(v).cwiseAbs().maxCoeff());
    tolerance_ = std::max(1e-6f * largest_, std::numeric_limits<float>::min());
    cell_ = 2 * tolerance_;
    head_.reserve(static_cast<std::size_t>(file.rows()));
    // Chains in decreasing order, so that each is walked from its first `v` line.
    for (Eigen::Index v = file.rows() - 1; v >= 0; --v) {
      if (!file.row(v).allFinite()) continue;
      const auto [head, added] = head_.try_emplace(key(cell_of(file.row(v))), static_cast<int>(v));
      if (!added) {
        next_[static_cast<std::size_t>(v)] = *head;
        *head = static_cast<int>(v);
      }
    }
  }

  /// The file vertex nearest to p within the tolerance (the first among equals), or −1.
  [[nodiscard]] int operator()(const Eigen::RowVector3f& p) const {
    // Far outside the file's extent no `v` line matches (and the cell number would not fit an int).
    if (!(p.cwiseAbs().maxCoeff() <= 2 * largest_)) return -1;
    const Eigen::Array3i c = cell_of(p);
    int best = -1;
    float best_distance = tolerance_;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int* head = head_.find(key(c + Eigen::Array3i(dx, dy, dz)));
          for (int v = head != nullptr ? *head : -1; v >= 0; v = next_[static_cast<std::size_t>(v)]) {
            const float d = (file_.row(v) - p).cwiseAbs().maxCoeff();
            if (d < best_distance || (d == best_distance && (best < 0 || v < best))) {
              best = v;
              best_distance = d;
            }
          }
        }
    return best;
  }

 private:
  [[nodiscard]] Eigen::Array3i cell_of(const Eigen::RowVector3f& p) const {
    // |p| ≤ 2 largest, so a cell number is within ±2 largest / (2e-6 largest) = ±1e6 (< 2^20).
    return (p.array() / cell_).floor().cast<int>().transpose();
  }
  [[nodiscard]] static std::uint64_t key(const Eigen::Array3i& c) {
    constexpr std::uint64_t kMask = (1u << 21) - 1;
    return (static_cast<std::uint64_t>(c[0]) & kMask) | (static_cast<std::uint64_t>(c[1]) & kMask) << 21 |
           (static_cast<std::uint64_t>(c[2]) & kMask) << 42;
  }

  const mesh::RowMatrixXf<3>& file_;
  float largest_ = 0, tolerance_ = 0, cell_ = 0;
  FlatMap<int> head_;
  std::vector<int> next_;
};

void identity(mesh::Mesh& m) {
  m.file_index = Eigen::VectorXi::LinSpaced(m.vertex_count(), 0, static_cast<int>(m.vertex_count()) - 1);
}

}  // namespace

void number_file_vertices(const std::filesystem::path& path, std::vector<mesh::Mesh>& meshes) {
  const std::string ext = lower_extension(path);
  if (is_gltf(path)) {
    for (mesh::Mesh& m : meshes) identity(m);
  } else if (ext == ".ply") {
    if (meshes.size() == 1 && ply_vertex_count(path) == meshes.front().vertex_count()) identity(meshes.front());
  } else if (ext == ".obj") {
    const mesh::RowMatrixXf<3> file = obj_positions(path);
    const PositionMatcher match(file);
    for (mesh::Mesh& m : meshes) {
      Eigen::VectorXi index(m.vertex_count());
      bool all = true;
      for (Eigen::Index v = 0; v < m.vertex_count() && all; ++v) all = (index[v] = match(m.positions.row(v))) >= 0;
      if (all) m.file_index = std::move(index);
    }
  }
}

}  // namespace cgamesh::io::detail
