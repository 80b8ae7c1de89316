// io::write_npy / io::read_npy: NumPy's .npy format for float64 matrices.

#include "cgamesh/io/npy.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "support/temp_dir.hpp"

namespace {

using cgamesh::FileError;
using cgamesh::io::read_npy;
using cgamesh::io::write_npy;
using cgamesh_test::TempDir;

std::string bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string error_of(const std::filesystem::path& p) {
  try {
    (void)read_npy(p, "array");
  } catch (const FileError& e) {
    return e.what();
  }
  return "no FileError";
}

TEST(Npy, RoundTripsInNumpysLayout) {
  TempDir dir;
  Eigen::MatrixXd values(3, 2);
  values << 1, 2, 3, 4.5, -6, 1e-300;
  write_npy(dir / "a.npy", values);
  EXPECT_EQ(read_npy(dir / "a.npy", "array"), values);
  const std::string bytes = bytes_of(dir / "a.npy");
  // Magic, version 1.0, the header dict, the data 64-byte aligned, row after row (C order).
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  EXPECT_NE(bytes.find("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }"), std::string::npos);
  const std::size_t data = bytes.size() - 6 * sizeof(double);
  EXPECT_EQ(data % 64, 0U);
  EXPECT_EQ(bytes[data - 1], '\n');
  double second = 0;
  std::memcpy(&second, bytes.data() + data + sizeof(double), sizeof(double));
  EXPECT_EQ(second, 2);  // (0, 1): C order
  write_npy(dir / "empty.npy", Eigen::MatrixXd(0, 4));
  EXPECT_EQ(read_npy(dir / "empty.npy", "array").cols(), 4);
}

TEST(Npy, ReadsVersionTwoHeaders) {
  TempDir dir;
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 1), }";
  header.append(64 - (12 + header.size() + 1) % 64, ' ');
  header += '\n';
  std::string bytes("\x93NUMPY\x02\x00", 8);
  for (int b = 0; b < 4; ++b) bytes += static_cast<char>((header.size() >> (8 * b)) & 0xff);
  bytes += header;
  const double x = 7.25;
  bytes.append(reinterpret_cast<const char*>(&x), sizeof x);
  std::ofstream(dir / "v2.npy", std::ios::binary) << bytes;
  EXPECT_EQ(read_npy(dir / "v2.npy", "array")(0, 0), 7.25);
}

TEST(Npy, BadFilesAreNamed) {
  TempDir dir;
  write_npy(dir / "a.npy", Eigen::MatrixXd::Ones(4, 3));
  const std::string good = bytes_of(dir / "a.npy");
  const auto variant = [&](const std::string& name, std::string bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return error_of(dir / name);
  };
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string b = good;
    b.replace(b.find(from), from.size(), to);
    return b;
  };
  EXPECT_NE(variant("t.npy", good.substr(0, good.size() - 8)).find("truncated"), std::string::npos);
  EXPECT_NE(variant("long.npy", good + std::string(8, '\0')).find("not 4x3 float64"), std::string::npos);
  EXPECT_NE(variant("x.npy", "hello").find("array " + (dir / "x.npy").string() + ": not a .npy file"),
            std::string::npos);
  EXPECT_NE(variant("f4.npy", with("<f8", "<f4")).find("float64"), std::string::npos);
  EXPECT_NE(variant("f.npy", with("False", "True ")).find("C order"), std::string::npos);
  EXPECT_NE(variant("3d.npy", with("(4, 3)", "(4,3,1)")).find("2-D"), std::string::npos);
  EXPECT_NE(variant("v9.npy", with(std::string("NUMPY\x01", 6), std::string("NUMPY\x09", 6))).find("version 9"),
            std::string::npos);
  // An absurd shape is refused by its size, not allocated.
  EXPECT_NE(variant("huge.npy", with("(4, 3)", "(9223372036854775807, 9)")).find("float64 values"),
            std::string::npos);
  EXPECT_EQ(error_of(dir / "missing.npy"), "cannot read the array " + (dir / "missing.npy").string());
}

}  // namespace
