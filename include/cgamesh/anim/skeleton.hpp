#pragma once
// Joint hierarchy: an editable form, and the flat runtime form built from it (ozz-style:
// parents before children, so a forward pass composes global transforms).

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cgamesh/anim/transform.hpp"
#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::anim {

/// One node of the hierarchy (a joint, or a plain transform node above the joints).
struct JointDesc {
  std::string name;
  int parent = -1;  ///< index into EditableSkeleton::joints, -1 for a root
  Transform rest;   ///< local transform relative to the parent
};

/// Editable skeleton: any order, edited freely, then built.
struct EditableSkeleton {
  std::vector<JointDesc> joints;
};

/// Flat runtime skeleton. Joint i's parent is < i (or -1).
class Skeleton {
 public:
  Skeleton() = default;

  /// Builds the flat form: joints are reordered so parents come first.
  /// @param[out] remap  if not null, remap[old index] = new index
  /// @throws InvalidInputError for a parent index out of range or a cycle.
  [[nodiscard]] static Skeleton build(const EditableSkeleton& editable, std::vector<int>* remap = nullptr);

  [[nodiscard]] int size() const noexcept { return static_cast<int>(parents_.size()); }
  [[nodiscard]] std::span<const int> parents() const noexcept { return parents_; }
  [[nodiscard]] std::span<const std::string> names() const noexcept { return names_; }
  [[nodiscard]] std::span<const Transform> rest() const noexcept { return rest_; }
  /// Rest local versors T R D (eq. 14), one per joint.
  [[nodiscard]] std::span<const cga::Versor<double>> rest_versors() const noexcept { return rest_versors_; }
  /// Index of the joint with this name, or -1.
  [[nodiscard]] int find(std::string_view name) const noexcept;

 private:
  std::vector<int> parents_;
  std::vector<std::string> names_;
  std::vector<Transform> rest_;
  std::vector<cga::Versor<double>> rest_versors_;
};

/// The first `shown` of `names`, comma-separated, then "… (N in all)" when there are more: for
/// error messages that list the valid names (of joints, clips) without printing hundreds.
[[nodiscard]] std::string name_list(std::span<const std::string> names, std::size_t shown = 20);

}  // namespace cgamesh::anim
