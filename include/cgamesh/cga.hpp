#pragma once
// Everything of the CGA G(4,1) algebra core.
#include "cgamesh/cga/blade.hpp"        // IWYU pragma: export
#include "cgamesh/cga/convert.hpp"      // IWYU pragma: export
#include "cgamesh/cga/exp_log.hpp"      // IWYU pragma: export
#include "cgamesh/cga/geometry.hpp"     // IWYU pragma: export
#include "cgamesh/cga/interpolation.hpp"  // IWYU pragma: export
#include "cgamesh/cga/multivector.hpp"  // IWYU pragma: export
#include "cgamesh/cga/operations.hpp"   // IWYU pragma: export
#include "cgamesh/cga/point_map.hpp"    // IWYU pragma: export
#include "cgamesh/cga/products.hpp"     // IWYU pragma: export
#include "cgamesh/cga/versors.hpp"      // IWYU pragma: export
