#pragma once
// The shared half of the methods whose handles select mesh vertices (spline, harmonic, arap):
// the selections (disjoint up to welded positions), the parts that hold no handle vertex split
// off and moved as `free_parts` says, and the frame that puts the two back together.

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "deform_method.hpp"

namespace cgamesh::deform::detail {

/// "weights" of the methods whose field is harmonic (spline, harmonic): mean_value or cotangent.
[[nodiscard]] LaplacianWeights parse_field_weights(const Json& j);

/// Resolves the spec's handles to mesh vertices into out.handles.
/// @throws InvalidInputError "spec.handles[h]: ..." for an index out of range, a selection of no
///         vertex, or a vertex (or welded position) in two handles.
void select_vertex_handles(const BindInput& in, BoundHandles& out);

/// The (sub-)mesh a field or ARAP is solved on: the parts that hold a handle vertex.
struct HandledShape {
  mesh::Mesh shape;                          ///< positions and faces of the handled parts
  std::vector<std::vector<int>> handles;     ///< out.handles in shape's vertex ids
  std::vector<int> blended;                  ///< mesh vertex of each shape vertex; empty: all of them
  std::vector<int> free_key;                 ///< per out.free vertex, the key that moves it, or −1
};

/// Splits off the parts (as `weights` joins vertices) that hold no handle vertex into out.free,
/// each moved by the key of the handle nearest to its centroid (`spline_ends`: handle 1 by the
/// last of out.keys) or kept, as `free_parts` says.
[[nodiscard]] HandledShape split_free_parts(const BindInput& in, LaplacianWeights weights, FreeParts free_parts,
                                            bool spline_ends, BoundHandles& out);

/// A method over a HandledShape: deform() moves the shape's vertices, the free parts follow.
class VertexHandleMethod : public BoundMethod {
 protected:
  VertexHandleMethod(const HandledShape& shape, const mesh::RowMatrixXf<3>& rest, std::vector<int> free);
  /// One frame of the handled shape: #shape×3 positions.
  virtual void deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                      ArapReport* report) const = 0;

 private:
  void apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out, ArapReport* report) const final;

  mesh::RowMatrixXf<3> rest_;  ///< #V×3, kept only when some part is free (blended_ not empty)
  std::vector<int> blended_, free_, free_key_;
};

/// `count` keys at rest: identities.
[[nodiscard]] std::vector<cga::Versor<double>> rest_keys(std::size_t count);

/// spline and harmonic: the handled shape by a motor blend (eq. 2).
class MotorBlendMethod final : public VertexHandleMethod {
 public:
  MotorBlendMethod(const HandledShape& shape, const BindInput& in, const BoundHandles& out, MotorBlend blend)
      : VertexHandleMethod(shape, in.rest, out.free), blend_(std::move(blend)) {}

 private:
  void deform(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out, ArapReport*) const override {
    blend_.deform(keys, out);
  }

  MotorBlend blend_;
};

}  // namespace cgamesh::deform::detail
