#pragma once
// The skin influences of one vertex as eq. (17) and glTF's JOINTS_0/WEIGHTS_0 take them: at most
// four, merged by joint, summing to 1. The one home of "keep the 4 largest and renormalise"
// (the loader, the blended vertices of section 4.3, the glTF writer).

#include <array>
#include <cstdint>
#include <span>

namespace cgamesh::mesh {

/// One joint's (palette entry's) weight on a vertex.
struct Influence {
  float weight = 0;
  std::uint16_t joint = 0;
};

/// At most four influences, by decreasing weight; unused slots are (joint 0, weight 0).
struct TopInfluences {
  std::array<std::uint16_t, 4> joints{};
  std::array<float, 4> weights{};
  int kept = 0;         ///< used slots (0 when no weight was positive)
  int distinct = 0;     ///< joints with a positive weight before keeping 4 (> 4: some were dropped)
  bool merged = false;  ///< some joint was listed more than once
};

/// Merges the influences on the same joint (weights added), ignores weights that are not
/// positive and finite, keeps the 4 largest (ties: the smaller joint first) and renormalises them
/// so that their sum is 1 to within half an ulp of 1 (the largest takes the remainder).
/// @param[in,out] all  the influences, in any order; reordered and merged in place
/// @return the kept influences; kept = 0 (all weights 0) when none is positive
[[nodiscard]] TopInfluences top_influences(std::span<Influence> all) noexcept;

}  // namespace cgamesh::mesh
