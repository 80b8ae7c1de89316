#include "cgamesh/anim/skeleton.hpp"

#include <string>

#include "cgamesh/errors.hpp"

namespace cgamesh::anim {

Skeleton Skeleton::build(const EditableSkeleton& editable, std::vector<int>* remap) {
  const int n = static_cast<int>(editable.joints.size());
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (int i = 0; i < n; ++i) {
    const int p = editable.joints[i].parent;
    if (p < -1 || p >= n || p == i)
      throw InvalidInputError("skeleton: joint '" + editable.joints[i].name + "' has an invalid parent index " +
                              std::to_string(p));
    (p < 0 ? roots : children[p]).push_back(i);
  }
  // Depth-first order from the roots puts every parent before its children; joints not
  // reached lie on a cycle.
  std::vector<int> order;
  order.reserve(n);
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int j = stack.back();
    stack.pop_back();
    order.push_back(j);
    for (auto it = children[j].rbegin(); it != children[j].rend(); ++it) stack.push_back(*it);
  }
  if (static_cast<int>(order.size()) != n) throw InvalidInputError("skeleton: the joint hierarchy has a cycle");
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) new_index[order[k]] = k;

  Skeleton s;
  s.parents_.reserve(n);
  for (int old : order) {
    const JointDesc& j = editable.joints[old];
    s.parents_.push_back(j.parent < 0 ? -1 : new_index[j.parent]);
    s.names_.push_back(j.name);
    s.rest_.push_back(j.rest);
    s.rest_versors_.push_back(j.rest.versor());
  }
  if (remap) *remap = std::move(new_index);
  return s;
}

std::string name_list(std::span<const std::string> names, std::size_t shown) {
  if (names.empty()) return "none";
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < shown; ++i) out += (i == 0 ? "'" : ", '") + names[i] + "'";
  if (names.size() > shown) out += ", … (" + std::to_string(names.size()) + " in all)";
  return out;
}

int Skeleton::find(std::string_view name) const noexcept {
  for (int i = 0; i < size(); ++i)
    if (names_[i] == name) return i;
  return -1;
}

}  // namespace cgamesh::anim
