// The spline method (paper section III): two handles fix the harmonic parameter λ at 0 and 1;
// the keys, or the joint motors FABRIK solves for an IK chain (III.C), are blended along λ by
// the spline's basis.

#include <memory>

#include "cgamesh/deform/fabrik.hpp"
#include "cgamesh/errors.hpp"
#include "vertex_handles.hpp"

namespace cgamesh::deform::detail {
namespace {

IkChain parse_ik(const Json& ik) {
  if (!ik.is_object() || !ik.contains("joints") || !ik["joints"].is_array() || !ik.contains("target"))
    bad("ik", "expected {\"joints\": [[x, y, z], ...], \"target\": [x, y, z]}");
  only_fields(ik, {"joints", "target"}, "ik.");
  IkChain chain;
  for (std::size_t i = 0; i < ik["joints"].size(); ++i)
    chain.joints.push_back(vector3(ik["joints"][i], "ik.joints[" + std::to_string(i) + "]"));
  chain.target = vector3(ik["target"], "ik.target");
  return chain;
}

void parse(const Json& j, DeformSpec& s, const std::filesystem::path&) {
  SplineSpec& f = s.fields.emplace<SplineSpec>();
  f.weights = parse_field_weights(j);
  f.free_parts = parse_free_parts(j);
  f.basis = choice<SplineBasis>(j, "basis",
                                {{"linear", SplineBasis::linear},
                                 {"quadratic_lagrange", SplineBasis::quadratic_lagrange},
                                 {"bezier", SplineBasis::bezier},
                                 {"bspline", SplineBasis::bspline}},
                                SplineBasis::bspline);
  f.degree = integer(j, "degree", f.degree);
  if (f.degree < 1) bad("degree", "expected an integer >= 1");
  parse_handles(j, s);
  if (j.contains("ik")) {
    f.ik = parse_ik(j["ik"]);
    if (j.contains("keys")) bad("keys", "give either keys or ik, not both");
  } else {
    parse_keys(j, s);
  }
}

std::unique_ptr<BoundMethod> bind(const BindInput& in, BoundHandles& out) {
  const auto& f = std::get<SplineSpec>(in.spec.fields);
  if (f.ik) {
    for (std::size_t j = 0; j < f.ik->joints.size(); ++j)
      in.reach.point(f.ik->joints[j], "ik.joints[" + std::to_string(j) + "]");
    in.reach.point(f.ik->target, "ik.target");
  }
  select_vertex_handles(in, out);
  // The counts after the selections, so that a bad index is named first.
  if (in.spec.handles.size() != 2) bad("handles", "the spline method takes 2 handles (lambda = 0 and lambda = 1)");
  SplineOptions spline;
  spline.harmonic.weights = f.weights;
  spline.basis = f.basis;
  spline.degree = f.degree;
  std::vector<double> probe(f.ik ? f.ik->joints.size() : in.spec.keys.size());
  try {
    spline_weights(spline, 0.0, probe);
  } catch (const InvalidInputError& e) {
    bad(f.ik ? "ik.joints" : "keys", e.what());
  }
  if (f.ik) {
    try {
      out.ik = fabrik(f.ik->joints, f.ik->target);
    } catch (const InvalidInputError& e) {
      bad("ik", e.what());
    }
    out.keys.assign(out.ik->motors.begin(), out.ik->motors.end());
  } else {
    out.keys = key_versors(in.spec);
  }
  const HandledShape shape = split_free_parts(in, f.weights, f.free_parts, true, out);
  return std::make_unique<MotorBlendMethod>(shape, in, out,
                                            bind_spline(shape.shape, shape.handles[0], shape.handles[1],
                                                        rest_keys(out.keys.size()), spline, in.options.blend));
}

}  // namespace

DeformMethodEntry spline_method() {
  return {"spline", {"weights", "free_parts", "basis", "degree", "ik"}, parse, bind};
}

}  // namespace cgamesh::deform::detail
