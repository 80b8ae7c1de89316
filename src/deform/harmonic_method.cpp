// The harmonic method (paper section IV): one key per handle, each vertex by the motors blended
// with its harmonic coordinates.

#include <memory>

#include "cgamesh/deform/harmonic_handles.hpp"
#include "vertex_handles.hpp"

namespace cgamesh::deform::detail {
namespace {

void parse(const Json& j, DeformSpec& s, const std::filesystem::path&) {
  s.fields = HarmonicSpec{parse_field_weights(j), parse_free_parts(j)};
  parse_handles(j, s);
  parse_keys(j, s);
}

std::unique_ptr<BoundMethod> bind(const BindInput& in, BoundHandles& out) {
  const auto& f = std::get<HarmonicSpec>(in.spec.fields);
  select_vertex_handles(in, out);
  check_one_key_per_handle(in.spec);  // after the selections, so that a bad index is named first
  out.keys = key_versors(in.spec);
  const HandledShape shape = split_free_parts(in, f.weights, f.free_parts, false, out);
  HarmonicOptions harmonic;
  harmonic.weights = f.weights;
  return std::make_unique<MotorBlendMethod>(
      shape, in, out,
      bind_harmonic_handles(shape.shape, shape.handles, rest_keys(out.keys.size()), harmonic, in.options.blend));
}

}  // namespace

DeformMethodEntry harmonic_method() { return {"harmonic", {"weights", "free_parts"}, parse, bind}; }

}  // namespace cgamesh::deform::detail
