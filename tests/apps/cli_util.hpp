#pragma once
// Running the built `cgamesh` binary from a test: its exit code, stdout and stderr, scratch
// directories, and readers for the OBJ / PLY files it writes.

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <system_error>
#include <unistd.h>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/temp_dir.hpp"

namespace cgamesh_cli_test {

namespace fs = std::filesystem;

/// The cgamesh executable built by CMake.
inline fs::path cli_path() { return fs::path(CGAMESH_CLI); }

using cgamesh_test::TempDir;

/// `text` quoted for /bin/sh.
inline std::string shell_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

inline std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  int code = -1;    ///< exit status, or -1 when the process did not exit normally
  std::string out;  ///< stdout
  std::string err;  ///< stderr
  std::string command;
};

inline std::ostream& operator<<(std::ostream& os, const Result& r) {
  return os << "$ " << r.command << "\nexit " << r.code << "\nstdout:\n" << r.out << "\nstderr:\n" << r.err;
}

/// Runs `argv` (program first) through the shell; stdout through a pipe, stderr through a
/// file in `err_dir` (removed afterwards).
inline Result run_program(const std::vector<std::string>& argv, const fs::path& err_dir) {
  static std::atomic<int> counter{0};
  const fs::path err_file =
      err_dir / ("stderr_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".txt");
  Result r;
  for (const std::string& a : argv) r.command += (r.command.empty() ? "" : " ") + shell_quote(a);
  const std::string cmd = r.command + " 2> " + shell_quote(err_file.string());
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "popen failed: " << std::strerror(errno);
    return r;
  }
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = read_file(err_file);
  std::error_code ec;
  fs::remove(err_file, ec);
  return r;
}

/// Runs `cgamesh ARGS...` (run_program).
inline Result run_cli(const std::vector<std::string>& args, const fs::path& err_dir) {
  std::vector<std::string> argv{cli_path().string()};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_program(argv, err_dir);
}

using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// The `KEY x y z` lines of an OBJ file (KEY "v" or "vn"), in order.
inline Points read_obj_rows(const fs::path& p, const std::string& key) {
  std::ifstream in(p);
  std::vector<double> xyz;
  std::string line;
  const std::string start = key + " ";
  while (std::getline(in, line)) {
    if (line.rfind(start, 0) != 0) continue;
    std::istringstream s(line.substr(start.size()));
    double x = 0, y = 0, z = 0;
    s >> x >> y >> z;
    EXPECT_TRUE(static_cast<bool>(s)) << p << ": bad " << key << " line '" << line << "'";
    xyz.insert(xyz.end(), {x, y, z});
  }
  Points out(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  std::copy(xyz.begin(), xyz.end(), out.data());
  return out;
}

/// The `v x y z` lines of an OBJ file, in order.
inline Points read_obj_vertices(const fs::path& p) { return read_obj_rows(p, "v"); }

/// The vertices of a binary little-endian PLY with float x y z, and maybe more float properties
/// after them (nx ny nz: the layout cgamesh writes).
inline Points read_ply_vertices(const fs::path& p) {
  const std::string bytes = read_file(p);
  const std::string end = "end_header\n";
  const std::size_t header_end = bytes.find(end);
  EXPECT_EQ(bytes.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u) << p;
  if (header_end == std::string::npos) {
    ADD_FAILURE() << p << ": no end_header";
    return {};
  }
  const std::string header = bytes.substr(0, header_end);
  const std::string tag = "element vertex ";
  const std::size_t at = header.find(tag);
  if (at == std::string::npos) {
    ADD_FAILURE() << p << ": no vertex element";
    return {};
  }
  const long count = std::stol(header.substr(at + tag.size()));
  const std::size_t xyz = header.find("property float x\nproperty float y\nproperty float z\n", at);
  EXPECT_NE(xyz, std::string::npos) << header;
  // Every property of the vertex element is a float (4 bytes).
  const std::size_t element_end = std::min(header.find("element ", at + tag.size()), header.size());
  std::size_t stride = 0;
  for (std::size_t q = header.find("property ", at); q < element_end; q = header.find("property ", q + 1)) {
    EXPECT_EQ(header.compare(q, 15, "property float "), 0) << header;
    stride += 4;
  }
  const std::size_t data = header_end + end.size();
  if (bytes.size() < data + static_cast<std::size_t>(count) * stride) {
    ADD_FAILURE() << p << ": file too short for " << count << " vertices";
    return {};
  }
  Points out(count, 3);
  for (long i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) {
      float f = 0;
      std::memcpy(&f, bytes.data() + data + static_cast<std::size_t>(i) * stride + static_cast<std::size_t>(4 * c),
                  4);  // little-endian host
      out(i, c) = f;
    }
  return out;
}

/// Largest distance between corresponding rows (infinity when the counts differ).
inline double max_distance(const Points& a, const Points& b) {
  if (a.rows() != b.rows()) return std::numeric_limits<double>::infinity();
  return a.rows() == 0 ? 0.0 : (a - b).rowwise().norm().maxCoeff();
}

/// Diagonal of the bounding box.
inline double diagonal(const Points& a) {
  return a.rows() == 0 ? 0.0 : (a.colwise().maxCoeff() - a.colwise().minCoeff()).norm();
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

inline nlohmann::json parse_json(const Result& r) {
  try {
    return nlohmann::json::parse(r.out);
  } catch (const nlohmann::json::exception& e) {
    ADD_FAILURE() << "stdout is not JSON (" << e.what() << "):\n" << r;
    return nlohmann::json::object();
  }
}

/// Runs the command and expects exit code 0.
inline Result run_ok(const cgamesh_test::TempDir& dir, const std::vector<std::string>& args) {
  Result r = run_cli(args, dir.path());
  EXPECT_EQ(r.code, 0) << r;
  return r;
}

/// Inputs in one directory, outputs in another that must stay empty after a failure.
struct Failure {
  cgamesh_test::TempDir inputs, outputs;
};

/// Runs a command that must fail with `code`, say something containing `message` on stderr, and
/// leave the output directory empty (no output, no temporary file).
inline void expect_failure(const Failure& f, const std::vector<std::string>& args, int code, const std::string& message,
                           const fs::path& output) {
  const Result r = run_cli(args, f.inputs.path());
  EXPECT_EQ(r.code, code) << r;
  EXPECT_FALSE(r.err.empty()) << r;
  EXPECT_TRUE(contains(r.err, message)) << "stderr should mention '" << message << "'\n" << r;
  EXPECT_FALSE(fs::exists(output)) << output;
  EXPECT_TRUE(f.outputs.entries().empty()) << r << "\nleft in the output directory: " << f.outputs.entries().front();
}

}  // namespace cgamesh_cli_test
