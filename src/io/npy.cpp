#include "cgamesh/io/npy.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"

namespace cgamesh::io {
namespace {

constexpr char kNpyMagic[] = "\x93NUMPY";

}  // namespace

void write_npy(const std::filesystem::path& path, const Eigen::MatrixXd& values) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(values.rows()) + ", " +
                       std::to_string(values.cols()) + "), }";
  // Format 1.0: magic, version, a 2-byte length, the header padded with spaces and a newline so
  // that the data starts at a multiple of 64 bytes.
  const std::size_t unpadded = 6 + 2 + 2 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::string bytes(kNpyMagic, 6);
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = values;
  static_assert(std::endian::native == std::endian::little, "the .npy writer assumes a little-endian machine");
  if (rows.size() > 0)
    bytes.append(reinterpret_cast<const char*>(rows.data()), static_cast<std::size_t>(rows.size()) * sizeof(double));
  write_file_atomically(path, bytes);
}

Eigen::MatrixXd read_npy(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec)) throw FileError("cannot read the " + what + " " + path.string());
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto bad = [&](const std::string& problem) -> FileError {
    return FileError(what + " " + path.string() + ": " + problem);
  };
  if (bytes.size() < 10 || bytes.compare(0, 6, kNpyMagic, 6) != 0) throw bad("not a .npy file");
  const auto major = static_cast<unsigned char>(bytes[6]);
  std::size_t length = 0, start = 0;
  if (major == 1) {
    length = static_cast<unsigned char>(bytes[8]) | static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw bad("truncated header");
    for (int b = 0; b < 4; ++b) length |= static_cast<std::size_t>(static_cast<unsigned char>(bytes[8 + b])) << (8 * b);
    start = 12;
  } else {
    throw bad("unknown .npy version " + std::to_string(major));
  }
  if (bytes.size() < start + length) throw bad("truncated header");
  std::string header = bytes.substr(start, length);
  header.erase(std::remove(header.begin(), header.end(), ' '), header.end());
  if (header.find("'descr':'<f8'") == std::string::npos) throw bad("expected float64 ('<f8') values");
  if (header.find("'fortran_order':False") == std::string::npos) throw bad("expected C order (fortran_order False)");
  const std::size_t shape = header.find("'shape':(");
  long long rows = -1, cols = -1;
  int used = 0;  // set only when the closing parenthesis follows the second extent
  if (shape == std::string::npos ||
      std::sscanf(header.c_str() + shape + 9, "%lld,%lld)%n", &rows, &cols, &used) != 2 || used == 0 || rows < 0 ||
      cols < 0)
    throw bad("expected a 2-D shape");
  const std::size_t data = start + length;
  // Compared with the values available (the header was checked to fit),, so that an absurd shape cannot overflow the product.
  const std::size_t available = (bytes.size() - data) / sizeof(double);
  if ((bytes.size() - data) % sizeof(double) != 0 ||
      (cols > 0 && static_cast<unsigned long long>(rows) > available / static_cast<unsigned long long>(cols)) ||
      static_cast<unsigned long long>(rows) * static_cast<unsigned long long>(cols) != available)
    throw bad("the data is not " + std::to_string(rows) + "x" + std::to_string(cols) + " float64 values (truncated?)");
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> values(rows, cols);
  if (available > 0) std::memcpy(values.data(), bytes.data() + data, available * sizeof(double));  // data() of none is null
  return values;
}

}  // namespace cgamesh::io
