#include "cgamesh/io/obj_reader.hpp"

#include <array>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <string_view>
#include <vector>

#include "cgamesh/errors.hpp"

namespace cgamesh::io {
namespace {

constexpr std::string_view kSpace = " \t\r";

/// The next word of `rest` (advanced past it), or empty.
std::string_view next_word(std::string_view& rest) {
  const std::size_t begin = rest.find_first_not_of(kSpace);
  if (begin == std::string_view::npos) {
    rest = {};
    return {};
  }
  rest.remove_prefix(begin);
  const std::size_t end = std::min(rest.find_first_of(kSpace), rest.size());
  const std::string_view word = rest.substr(0, end);
  rest.remove_prefix(end);
  return word;
}

/// `word` as a number, or NaN; a leading '+' is accepted, as C's strtod does.
double number(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  double x = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), x);
  return ec == std::errc() && end == word.data() + word.size() ? x : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

ObjPolygons read_obj(const std::filesystem::path& path, const ObjReadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw FileError("cannot read the " + options.what + " " + path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read the " + options.what + " " + path.string());
  std::vector<double> xyz;
  std::vector<std::array<int, 3>> faces;
  std::vector<int> corners;
  std::string line;
  for (long long number_of_line = 1; std::getline(in, line); ++number_of_line) {
    const auto bad = [&](const std::string& what) {
      throw FileError(options.what + " " + path.string() + ":" + std::to_string(number_of_line) + ": " + what);
    };
    std::string_view rest = line;
    const std::string_view tag = next_word(rest);
    if (tag == "v") {
      bool finite = true;
      for (int c = 0; c < 3; ++c) {
        const double x = number(next_word(rest));
        finite = finite && std::isfinite(x);
        xyz.push_back(x);
      }
      if (options.strict && !finite) bad("expected v x y z (finite numbers)");
    } else if (tag == "f" && options.strict) {
      corners.clear();
      const long long vertices = static_cast<long long>(xyz.size() / 3);
      for (std::string_view word; !(word = next_word(rest)).empty();) {
        long long index = 0;
        const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), index);
        if (error != std::errc() || (end != word.data() + word.size() && *end != '/'))
          bad("expected f with vertex indices, got '" + std::string(word) + "'");
        // OBJ indices start at 1; negative ones count back from the last vertex so far.
        const long long resolved = index > 0 ? index - 1 : vertices + index;
        if (index == 0 || resolved < 0 || resolved >= vertices)
          bad("vertex index " + std::string(word) + " out of range (" + std::to_string(vertices) +
              " vertices so far)");
        corners.push_back(static_cast<int>(resolved));
      }
      if (corners.size() < 3) bad("a face needs 3 vertices or more");
      for (std::size_t c = 1; c + 1 < corners.size(); ++c) faces.push_back({corners[0], corners[c], corners[c + 1]});
    }
  }
  ObjPolygons out;
  out.vertices = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  out.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    out.faces.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return out;
}

}  // namespace cgamesh::io
