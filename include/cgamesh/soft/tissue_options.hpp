#pragma once
// The tunables of soft tissue (soft/tissue.hpp), with their units and defaults. Lengths are in
// model units (metres for glTF), times in seconds, masses in kilograms.

#include <Eigen/Core>

namespace cgamesh::soft {

struct TissueOptions {
  /// Areal density, mass per unit of surface area (kg per square model unit). Skin and the
  /// tissue under it: about 10 kg/m².
  double density = 10.0;
  /// Compliance (inverse stiffness, model units per newton) of each particle's attachment to
  /// its skinned target: what holds the tissue on the body. 0: rigidly attached.
  double attachment_compliance = 1e-4;
  /// Compliance of the stretch links along edges. 0: inextensible.
  double stretch_compliance = 1e-7;
  /// Compliance of the bending links across edges (between the two corners opposite an edge).
  double bend_compliance = 1e-3;
  /// Pre-tension: stretch links rest this fraction shorter than the skinned edge, in [0, 1):
  /// skin under tension, which makes a wound gape.
  double pretension = 0.1;
  /// Velocity damping per second: speeds decay as exp(−damping · t) with no force.
  double damping = 5.0;
  /// Fixed substep (s), independent of the frame rate (small steps, Macklin et al. 2019).
  double substep = 1.0 / 900.0;
  /// Gravity (model units per s²); glTF's up is +y.
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};
  /// Radius of the simulated region around each wound (model units); 0: 10 % of the model's
  /// diagonal. Outside it the tissue is the skinned surface, at no cost.
  double region_radius = 0;
  /// Particles within this distance of a wound's new vertices are released from their
  /// attachments (model units); 0: a quarter of the region radius.
  double release_margin = 0;
  /// The region's budget of vertices, which bounds the cost of a step (about 0.35 µs per
  /// vertex and frame of 1/90 s on one core): when the region would hold more (a fine mesh),
  /// its radius and the release margin shrink by one factor until it holds this many. The
  /// default keeps a 90 Hz frame under a millisecond. 0: no budget.
  int max_particles = 2000;

  /// @throws InvalidInputError naming the field for a negative, NaN or infinite value, a zero
  ///         substep (or one above 0.1 s), or a pre-tension outside [0, 1).
  void validate() const;
  [[nodiscard]] bool operator==(const TissueOptions&) const = default;
};

}  // namespace cgamesh::soft
