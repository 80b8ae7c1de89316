#pragma once
// The one way a number is written into a message.

#include <sstream>
#include <string>

namespace cgamesh {

/// `x` as an ostream prints it (6 significant digits): for messages and warnings.
[[nodiscard]] inline std::string number_text(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace cgamesh
