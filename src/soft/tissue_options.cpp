#include "cgamesh/soft/tissue_options.hpp"

#include <cmath>
#include <string>

#include "cgamesh/errors.hpp"

namespace cgamesh::soft {

void TissueOptions::validate() const {
  const auto non_negative = [](double value, const char* field) {
    if (!(value >= 0) || !std::isfinite(value))
      throw InvalidInputError(std::string("tissue options: ") + field + " must be a finite number >= 0, got " +
                              std::to_string(value));
  };
  non_negative(density, "density");
  non_negative(attachment_compliance, "attachment_compliance");
  non_negative(stretch_compliance, "stretch_compliance");
  non_negative(bend_compliance, "bend_compliance");
  non_negative(damping, "damping");
  non_negative(region_radius, "region_radius");
  non_negative(release_margin, "release_margin");
  if (!(density > 0)) throw InvalidInputError("tissue options: density must be > 0 (particles need mass)");
  if (!(pretension >= 0 && pretension < 1))
    throw InvalidInputError("tissue options: pretension must be in [0, 1), got " + std::to_string(pretension));
  if (!(substep > 0 && substep <= 0.1))
    throw InvalidInputError("tissue options: substep must be in (0, 0.1] seconds, got " + std::to_string(substep));
  if (!gravity.allFinite()) throw InvalidInputError("tissue options: gravity must be finite");
  if (max_particles < 0)
    throw InvalidInputError("tissue options: max_particles must be >= 0 (0: no budget), got " +
                            std::to_string(max_particles));
}

}  // namespace cgamesh::soft
